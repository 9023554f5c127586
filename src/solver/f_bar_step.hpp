#pragma once
// F-bar (f_bar.hpp) in the implicit step: the cells' volume averages at a trial increment, the
// points' F-bar step gradient, and the tangent's coupling of the points of a cell through
// J_bar_c, one rank-one block u v^T per cell over the union of its points' stencils:
//   u_ia = sum_p V0_p H_p : B_ia(x_p),   v_kc = sum_q w_q j_q dF_q^-T : B_kc(x_q),
// since dJ_bar = sum_q w_q j_q dF_q^-T : d(dF_q) and d(dF_q) = sum_k,c B_kc du_kc, where
// B_kc = e_c grad N_k^T, plus N_k / r e_3 e_3^T for c = r in axisymmetry (the hoop stretch)
// (H_p = dG_p/dJ_bar, step_tangent.hpp).
#include "step_tangent.hpp"
#include "talus/core/particles.hpp"
#include "talus/linalg/lattice_assembler.hpp"
#include "talus/solver/f_bar.hpp"
#include "talus/solver/particle_share.hpp"

#include <algorithm>
#include <fmt/format.h>
#include <span>
#include <stdexcept>
#include <vector>

namespace talus {

template <int Dim, bool Axisymmetric> class FBarStep {
  using V = Vec<Dim>;
  using M = Mat<Dim>;
  using Components = StepComponents<Dim, Axisymmetric>;

public:
  /// `out_of_plane`: plane strain's volume change spread over three axes
  /// (solver.f_bar_out_of_plane).
  explicit FBarStep(bool out_of_plane = false) : axes_(out_of_plane ? 3 : Components::kAxes) {}

  /// Groups the points by cell at the step's start; `nodes`: the step's active node count.
  void prepare(const Grid<Dim>& grid, const Particles<Dim>& points, Index nodes) {
    cells_.build(grid, points);
    resize(points.size());
    node_slot_.assign(static_cast<std::size_t>(nodes), -1);
  }
  void resize(Index points) {
    trial_j_.resize(at(points), 1.0);
    dG_dJbar_.resize(at(points), StepVector<Dim, Axisymmetric>::Zero());
  }

  /// F-bar couples the points of a cell: a share must hold every point of the cells it
  /// reaches. (A distributed run will need shares made of whole cells, or the cell averages
  /// exchanged; the serial solver is one share.)
  void require_whole_cells(const ParticleShare& share) const {
    const auto& points = cells_.points();
    for (Index p = share.begin; p < share.end; ++p) {
      const Index c = cells_.cell_of(p);
      for (Index k = cells_.begin(c); k < cells_.end(c); ++k)
        if (!share.contains(points[at(k)]))
          throw std::invalid_argument(fmt::format(
              "F-bar: share {} holds point {} but not point {} of the same cell; F-bar needs "
              "shares made of whole cells",
              share.index, p, points[at(k)]));
    }
  }

  /// Replaces the trial F of the share's points by dF_bar F_n, dF_bar = (J_bar_c / j_p)^(1/n)
  /// dF_p over n axes (StepComponents', or three out of plane); false if a point or a cell average
  /// has lost its volume (j <= 0). step_gradient(p) is the point's 3x3 trial step gradient.
  template <class StepGradient>
  bool apply(const ParticleShare& share, const Particles<Dim>& P, StepGradient&& step_gradient,
             std::vector<Mat3>& trial_F) {
    cell_j_bar_.resize(at(cells_.cell_count()));
    for (Index p = share.begin; p < share.end; ++p) {
      trial_j_[at(p)] = step_gradient(p).determinant();
      cell_j_bar_[at(cells_.cell_of(p))] = 0.0;
    }
    for (Index p = share.begin; p < share.end; ++p)
      cell_j_bar_[at(cells_.cell_of(p))] += cells_.weight(p) * trial_j_[at(p)];
    for (Index p = share.begin; p < share.end; ++p) {
      const double j = trial_j_[at(p)], j_bar = j_bar_of(p);
      if (!(j > 0 && j_bar > 0))
        return false;
      trial_F[at(p)] = scaled(step_gradient(p), f_bar_scale(axes_, j_bar / j)) * P.F[at(p)];
    }
    return true;
  }

  /// j_p / J_bar_c: the true current volume over the F-bar one.
  double volume_ratio(Index p) const { return trial_j_[at(p)] / j_bar_of(p); }

  /// dG/d(dF) of point p at fixed J_bar; keeps dG/dJ_bar for the cell coupling.
  StepTangent<Dim, Axisymmetric> step_tangent_of(Index p, const Mat3& dF, const Mat3& Fn,
                                                 const StressTangent& st) {
    return f_bar_step_tangent<Dim, Axisymmetric>(dF, Fn, st, trial_j_[at(p)], j_bar_of(p), axes_,
                                                 dG_dJbar_[at(p)]);
  }

  /// f(nodes) with the union of the stencils of each cell's points, for every cell of the share
  /// (each once, at the first of its points): the nodes the cell's coupling block spans.
  template <class Map, class F>
  void for_each_cell_nodes(const ParticleShare& share, const Map& map, F&& f) {
    for (Index first = share.begin; first < share.end; ++first)
      if (is_first_of_cell(first)) {
        cells_.stencil_union(cells_.cell_of(first), map, cell_nodes_);
        f(std::span<const Index>(cell_nodes_));
      }
  }

  /// Adds the rank-one coupling u v^T of every cell of the share.
  template <class Map, class StepGradient>
  void add_coupling(const ParticleShare& share, const Map& map, const Particles<Dim>& P,
                    StepGradient&& step_gradient, LatticeAssembler<Dim>& tangent) {
    const auto& points = cells_.points();
    for (Index first = share.begin; first < share.end; ++first) {
      if (!is_first_of_cell(first))
        continue;
      const Index c = cells_.cell_of(first);
      cells_.stencil_union(c, map, cell_nodes_);
      const auto n = static_cast<Eigen::Index>(Dim * cell_nodes_.size());
      u_.setZero(n);
      v_.setZero(n);
      for (std::size_t k = 0; k < cell_nodes_.size(); ++k)
        node_slot_[at(cell_nodes_[k])] = static_cast<Index>(k);
      for (Index k = cells_.begin(c); k < cells_.end(c); ++k) {
        const Index p = points[at(k)];
        const StepVector<Dim, Axisymmetric> H = P.volume0[at(p)] * dG_dJbar_[at(p)];
        const M H_block =
            Eigen::Map<const Eigen::Matrix<double, Dim, Dim, Eigen::RowMajor>>(H.data());
        const Mat3 dF = step_gradient(p); // block diagonal: the block and the hoop stretch
        const M dFinv_T = M(dF.template topLeftCorner<Dim, Dim>()).inverse().transpose();
        const double wj = cells_.weight(p) * trial_j_[at(p)];
        const double r = P.x[at(p)][0];
        map.for_each_node_of(p, [&](Index node, double w, const V& grad) {
          const Eigen::Index slot = Dim * node_slot_[at(node)];
          u_.template segment<Dim>(slot) += H_block * grad;
          v_.template segment<Dim>(slot) += wj * (dFinv_T * grad);
          if constexpr (Axisymmetric) { // the hoop stretch moves with the radial component
            u_[slot] += H[Components::kHoop] * w / r;
            v_[slot] += wj * w / (r * dF(2, 2));
          }
        });
      }
      for (const Index node : cell_nodes_)
        node_slot_[at(node)] = -1;
      block_.noalias() = u_ * v_.transpose();
      tangent.add_block(cell_nodes_, block_);
    }
  }

private:
  /// k dF over the F-bar axes (plane strain's default keeps dF33 = 1).
  Mat3 scaled(Mat3 dF, double k) const {
    if (axes_ == 3)
      return k * dF;
    dF.template topLeftCorner<Dim, Dim>() *= k;
    return dF;
  }
  double j_bar_of(Index p) const { return cell_j_bar_[at(cells_.cell_of(p))]; }
  bool is_first_of_cell(Index p) const {
    return cells_.points()[at(cells_.begin(cells_.cell_of(p)))] == p;
  }

  int axes_;                       ///< the axes a step's volume change spreads over
  FBarCells cells_;                ///< the points of each cell, at the step's start
  std::vector<double> trial_j_;    ///< per point: det dF at the trial increment
  std::vector<double> cell_j_bar_; ///< per cell: volume-weighted average of j
  std::vector<StepVector<Dim, Axisymmetric>> dG_dJbar_; ///< per point: H = dG/dJ_bar
  std::vector<Index> node_slot_;  ///< per active node: its place in cell_nodes_, -1 outside
  std::vector<Index> cell_nodes_; ///< the nodes of the cell being coupled
  Eigen::VectorXd u_, v_;         ///< the cell's rank-one factors, Dim entries per node
  Eigen::MatrixXd block_;         ///< u v^T
};

} // namespace talus
