#pragma once
// The nodal pore pressure an implicit consolidation step starts from, and where it is held
// (consolidation.hpp). The points carry p; a step starts from its mass-weighted projection on
// the nodes. A node is drained, its p held at the water table's (zero without one), when it
// lies on a grid face the case declares drained or on the body's free surface: a node next to
// a cell of the grid that holds no point (the grid's outside is a wall, impermeable). Both are
// sums over the points, made whole across ranks by the halo.
#include "talus/core/particles.hpp"
#include "talus/grid/particle_grid_map.hpp"
#include "talus/parallel/node_halo.hpp"
#include "talus/scene/pore_water.hpp"

#include <array>
#include <cmath>
#include <vector>

namespace talus {

/// pressure[n] = sum_p N m p / sum_p N m over the points, with `mass` the nodes' whole masses.
template <int Dim, class Shape>
void project_node_pressure(const ParticleGridMap<Dim, Shape>& map, const Particles<Dim>& P,
                           NodeHalo<Dim>& halo, const std::vector<double>& mass,
                           std::vector<double>& pressure) {
  pressure.assign(mass.size(), 0.0);
  for (Index n = 0; n < map.node_count(); ++n)
    map.for_each_particle_of(n, [&](Index p, double w, const Vec<Dim>&) {
      pressure[at(n)] += w * P.mass[at(p)] * P.pore_pressure[at(p)];
    });
  const typename NodeHalo<Dim>::Field field{pressure.data(), 1};
  halo.sum({&field, 1});
  for (std::size_t n = 0; n < pressure.size(); ++n)
    pressure[n] = mass[n] > 0 ? pressure[n] / mass[n] : 0.0;
}

/// drained[n]: node n lies on a face with drained[face] or next to a grid cell without points.
template <int Dim, class Shape>
void mark_drained_nodes(const ParticleGridMap<Dim, Shape>& map, const Particles<Dim>& P,
                        NodeHalo<Dim>& halo, const std::array<bool, 6>& drained_face,
                        std::vector<char>& drained) {
  constexpr int kCorners = 1 << Dim;
  const auto& nodes = map.nodes();
  const auto& grid = nodes.grid();
  // Per node, the points in each of the cells it is a corner of (cell k: the node minus bit
  // d of k along each d).
  std::vector<double> count(at(map.node_count()) * kCorners, 0.0);
  for (Index p = 0; p < P.size(); ++p) {
    const std::array<Index, Dim> cell = grid.cell_of(P.x[at(p)]);
    for (int k = 0; k < kCorners; ++k) {
      std::array<Index, Dim> ijk = cell;
      for (int d = 0; d < Dim; ++d)
        ijk[at(d)] += (k >> d) & 1;
      if (const Index n = nodes.find(ijk); n >= 0)
        count[at(n) * kCorners + at(k)] += 1.0;
    }
  }
  const typename NodeHalo<Dim>::Field field{count.data(), kCorners};
  halo.sum({&field, 1});
  drained.assign(at(map.node_count()), 0);
  for (Index n = 0; n < map.node_count(); ++n) {
    const std::array<Index, Dim> ijk = nodes.ijk(n);
    bool open = false;
    for (int d = 0; d < Dim; ++d)
      open = open || (drained_face[at(2 * d)] && ijk[at(d)] <= 0) ||
             (drained_face[at(2 * d + 1)] && ijk[at(d)] >= grid.cells(d));
    for (int k = 0; k < kCorners && !open; ++k) {
      bool inside = true; // the cell lies in the grid
      for (int d = 0; d < Dim; ++d) {
        const Index c = ijk[at(d)] - ((k >> d) & 1);
        inside = inside && c >= 0 && c < grid.cells(d);
      }
      open = inside && count[at(n) * kCorners + at(k)] == 0.0;
    }
    drained[at(n)] = open;
  }
}

} // namespace talus
