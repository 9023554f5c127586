#pragma once
// Tractions act on the boundary of the body, not at the material points' centres. Mapping a
// traction point's force with the point's own shape functions (as a body force) hands part of
// it to nodes inside the body, and on a coarse grid to nodes on a support, where it never
// loads the material (one cell: a quarter of a side load is lost). A surface load therefore
// carries the offset from its point's centre to the midpoint of the loaded voxel face; the face
// midpoint follows the deformation, x_p + F_p r, and its force goes to the grid through the
// bilinear hats of the cell that holds it, clamped into the point's stencil so that only nodes
// the point reaches receive it.
#include "talus/core/particles.hpp"
#include "talus/grid/active_nodes.hpp"

#include <algorithm>
#include <cmath>

namespace talus {

template <int Dim> struct SurfaceLoad {
  Index particle = 0;
  /// reference offset from the point's centre to the loaded face midpoint
  Vec<Dim> offset = Vec<Dim>::Zero();
  Vec<Dim> force = Vec<Dim>::Zero(); ///< N (per unit thickness in 2D)
  /// Implicit analyses: applied in full from the first step instead of following the load
  /// factor (TractionSpec::constant).
  bool constant = false;
};

/// Calls add(node, weight) for the active nodes that share the load's force, with weights that
/// sum to one: the multilinear hats of the cell that holds the face midpoint. `stencil_first`
/// and `stencil_width` bound the nodes the point reaches (ParticleGridMap::stencil(p).start and
/// Shape::kWidth).
template <int Dim, class Add>
void for_each_surface_load_node(const ActiveNodes<Dim>& nodes, const Particles<Dim>& particles,
                                const SurfaceLoad<Dim>& load,
                                const std::array<Index, Dim>& stencil_first, int stencil_width,
                                Add&& add) {
  const Grid<Dim>& grid = nodes.grid();
  const auto s = static_cast<std::size_t>(load.particle);
  const Vec<Dim> x = particles.x[s] + particles.grid_F(s) * load.offset - grid.origin();
  const double h = grid.cell_size();
  std::array<Index, Dim> cell{};
  std::array<double, Dim> xi{};
  for (int d = 0; d < Dim; ++d) {
    const double lo = static_cast<double>(stencil_first[d]);
    const double hi = lo + static_cast<double>(stencil_width - 1);
    const double u = std::clamp(x[d] / h, lo, hi);
    cell[d] = std::min(static_cast<Index>(std::floor(u)), static_cast<Index>(hi) - 1);
    xi[d] = u - static_cast<double>(cell[d]);
  }
  for (int corner = 0; corner < (1 << Dim); ++corner) {
    double w = 1.0;
    std::array<Index, Dim> node = cell;
    for (int d = 0; d < Dim; ++d) {
      const bool upper = (corner >> d) & 1;
      w *= upper ? xi[d] : 1.0 - xi[d];
      node[d] += upper ? 1 : 0;
    }
    if (w > 0.0)
      add(nodes.find(node), w); // inside the point's stencil: active
  }
}

} // namespace talus
