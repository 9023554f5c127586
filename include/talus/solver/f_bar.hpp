#pragma once
// F-bar: the remedy for volumetric locking of low-order MPM (de Souza Neto et al. 1996, IJSS
// 33; for MPM Coombs, Charlton, Cortis & Augarde 2018, CMAME 338). Near-incompressible
// response (nu -> 1/2, or isochoric plastic flow with psi = 0) asks every material point to
// keep its volume, more constraints than a linear or GIMP grid has freedoms, and the body
// locks: bending stiffens, collapse loads rise with E. F-bar relaxes the constraint to one
// per cell: the volume change of a step is averaged over the points of the cell,
//   J_bar_c = sum_q w_q j_q,   j_q = det dF_q,   w_q = v_q / sum_{q in c} v_q,
// and each point's step gradient keeps its own isochoric part with the cell's volume change,
//   dF_bar_p = (J_bar_c / j_p)^(1/n) dF_p
// over the n axes the volume change spreads over: three in 3D and axisymmetry; in plane strain
// (F33 = 1, det dF_p the in-plane determinant) the in-plane block, n = 2, or with
// solver.f_bar_out_of_plane all three, n = 3, as in a 3D slab between z rollers.
// The stress is tau(dF_bar F_n); the internal force keeps the true current volume,
//   f_i = sum_p V0_p (j_p / J_bar_c) tau_p dF_p^-T grad N_i(x_p^n),
// and its tangent gains a rank-one coupling per cell through J_bar_c (implicit_solver.cpp).
#include "talus/core/particles.hpp"
#include "talus/grid/grid.hpp"

#include <algorithm>
#include <vector>

namespace talus {

/// The points grouped by the grid cell that holds their centre, with their volume weights.
class FBarCells {
public:
  /// Groups the points by cell at their current positions; weights from current volumes.
  template <int Dim> void build(const Grid<Dim>& grid, const Particles<Dim>& particles);

  Index cell_count() const { return static_cast<Index>(begin_.size()) - 1; }
  /// Points of cell c: points()[begin(c) .. end(c)).
  Index begin(Index c) const { return begin_[static_cast<std::size_t>(c)]; }
  Index end(Index c) const { return begin_[static_cast<std::size_t>(c) + 1]; }
  const std::vector<Index>& points() const { return points_; }
  Index cell_of(Index p) const { return cell_of_[static_cast<std::size_t>(p)]; }
  /// v_p / (total volume of p's cell).
  double weight(Index p) const { return weight_[static_cast<std::size_t>(p)]; }
  /// nodes: the union of the stencils of cell c's points on map, ascending.
  template <class Map>
  void stencil_union(Index c, const Map& map, std::vector<Index>& nodes) const {
    nodes.clear();
    for (Index k = begin(c); k < end(c); ++k) {
      const auto stencil = map.stencil_nodes(points_[static_cast<std::size_t>(k)]);
      nodes.insert(nodes.end(), stencil.begin(), stencil.end());
    }
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  }

private:
  std::vector<Index> begin_{0}; ///< CSR offsets into points_, one more than the cells
  std::vector<Index> points_;   ///< point indices grouped by cell
  std::vector<Index> cell_of_;  ///< per point: index of its (non-empty) cell
  std::vector<double> weight_;  ///< per point: volume fraction within its cell
};

} // namespace talus
