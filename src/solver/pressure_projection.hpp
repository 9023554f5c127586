#pragma once
// The polynomial pressure projection (Bochev & Dohrmann 2006 for Stokes; White & Borja 2008 for
// Biot's equations) in an implicit consolidation step. Equal-order displacement and pressure
// do not satisfy the inf-sup condition: near the undrained limit (a step much shorter than
// h^2 / c_v, incompressible constituents) the pressure checkerboards. The mass balance gains,
// per grid cell c of the step's start,
//   r_i += s sum_{p in c} tau_p V_p N_i (dp_p - dp_c),   dp_c = sum_{p in c} w_p dp_p,
// the points' increments less their cell's volume average (w_p = V_p / V_c: the L2 projection
// on the cell's constants), tau = f alpha^2 / (2 G) per material (f: solver.pressure_projection).
// It vanishes for a pressure constant in a cell and so leaves the drained limit, and the
// converged consolidation, alone. Its tangent over the union of the cell's stencils is
//   s^2 [sum_p tau_p V_p N_i N_j - b_i a_j],  b_i = sum_p tau_p V_p N_i,  a_j = sum_p w_p N_j.
// The cells couple their points: a share must hold whole cells (as F-bar's).
#include "talus/core/particles.hpp"
#include "talus/linalg/lattice_assembler.hpp"
#include "talus/solver/f_bar.hpp"
#include "talus/solver/particle_share.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <span>
#include <vector>

namespace talus {

template <int Dim> class PressureProjection {
public:
  /// Groups the points by cell at the step's start; tau per material.
  void prepare(const Grid<Dim>& grid, const Particles<Dim>& P, std::vector<double> tau) {
    cells_.build(grid, P);
    tau_ = std::move(tau);
  }

  /// Calls f(node, r_i) with the projection's terms of every cell of the share; dp(p): the
  /// point's trial increment.
  template <class Map, class Increment, class F>
  void for_each_residual(const ParticleShare& share, const Map& map, const Particles<Dim>& P,
                         Increment&& dp, double s, F&& f) const {
    for (Index first = share.begin; first < share.end; ++first) {
      if (!is_first_of_cell(first))
        continue;
      const Index c = cells_.cell_of(first);
      double mean = 0;
      for (Index k = cells_.begin(c); k < cells_.end(c); ++k) {
        const Index p = cells_.points()[at(k)];
        mean += cells_.weight(p) * dp(p);
      }
      for (Index k = cells_.begin(c); k < cells_.end(c); ++k) {
        const Index p = cells_.points()[at(k)];
        const double scale = s * tau_of(P, p) * P.volume[at(p)] * (dp(p) - mean);
        map.for_each_node_of(p, [&](Index n, double w, const Vec<Dim>&) { f(n, scale * w); });
      }
    }
  }

  /// f(nodes) with the union of the stencils of each cell of the share: the blocks' nodes.
  template <class Map, class F>
  void for_each_cell_nodes(const ParticleShare& share, const Map& map, F&& f) const {
    for (Index first = share.begin; first < share.end; ++first)
      if (is_first_of_cell(first)) {
        cells_.stencil_union(cells_.cell_of(first), map, cell_nodes_);
        f(std::span<const Index>(cell_nodes_));
      }
  }

  /// Adds every cell's block of the share to the pressure field's rows and columns.
  template <class Map>
  void add_tangent(const ParticleShare& share, const Map& map, const Particles<Dim>& P, double s,
                   int field, LatticeAssembler<Dim>& tangent) const {
    for (Index first = share.begin; first < share.end; ++first) {
      if (!is_first_of_cell(first))
        continue;
      const Index c = cells_.cell_of(first);
      cells_.stencil_union(c, map, cell_nodes_);
      const auto n = static_cast<Eigen::Index>(cell_nodes_.size());
      block_.setZero(n, n);
      a_.setZero(n);
      b_.setZero(n);
      for (Index k = cells_.begin(c); k < cells_.end(c); ++k) {
        const Index p = cells_.points()[at(k)];
        const double tv = tau_of(P, p) * P.volume[at(p)];
        weights_.setZero(n);
        map.for_each_node_of(
            p, [&](Index node, double w, const Vec<Dim>&) { weights_[slot(node)] += w; });
        block_.noalias() += tv * weights_ * weights_.transpose();
        b_ += tv * weights_;
        a_ += cells_.weight(p) * weights_;
      }
      block_.noalias() -= b_ * a_.transpose();
      block_ *= s * s;
      tangent.add_block(cell_nodes_, block_, field);
    }
  }

private:
  double tau_of(const Particles<Dim>& P, Index p) const { return tau_[at(P.material[at(p)])]; }
  bool is_first_of_cell(Index p) const {
    return cells_.points()[at(cells_.begin(cells_.cell_of(p)))] == p;
  }
  /// The place of a node in cell_nodes_ (ascending).
  Eigen::Index slot(Index node) const {
    return std::lower_bound(cell_nodes_.begin(), cell_nodes_.end(), node) - cell_nodes_.begin();
  }

  FBarCells cells_;         ///< the points of each cell, at the step's start
  std::vector<double> tau_; ///< per material: f alpha^2 / (2 G), 1/Pa
  // Scratch of the cell in hand.
  mutable std::vector<Index> cell_nodes_;
  mutable Eigen::VectorXd weights_, a_, b_;
  mutable Eigen::MatrixXd block_;
};

} // namespace talus
