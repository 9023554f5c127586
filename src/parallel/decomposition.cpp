#include "talus/parallel/decomposition.hpp"

#include <algorithm>
#include <map>

namespace talus {

template <int Dim>
Decomposition<Dim> Decomposition<Dim>::partition(const Communicator& comm, const Grid<Dim>& grid,
                                                 std::span<const Vec<Dim>> positions) {
  Decomposition<Dim> out;
  out.comm_ = &comm;
  out.grid_ = grid;
  // Points per cell, each cell once per rank, at its centre.
  std::map<std::array<Index, Dim>, double> per_cell;
  const double h = grid.cell_size();
  for (const Vec<Dim>& x : positions)
    per_cell[grid.cell_of(x)] += 1.0;
  std::vector<double> centres, weights;
  for (const auto& [cell, count] : per_cell) {
    for (int d = 0; d < Dim; ++d)
      centres.push_back(grid.origin()[d] +
                        (static_cast<double>(cell[static_cast<std::size_t>(d)]) + 0.5) * h);
    weights.push_back(count);
  }
  if (comm.distributed()) {
    out.boxes_ = partition_boxes(Dim, centres, weights, comm.mpi());
    // The boxes tile the points' bounding box; the faces on it move out to infinity, so the
    // boxes tile all space and a point that leaves the bounding box still lies in a box.
    for (int d = 0; d < Dim; ++d) {
      const auto k = static_cast<std::size_t>(d);
      double lo = INFINITY, hi = -INFINITY;
      for (const PartBox& b : out.boxes_) {
        lo = std::min(lo, b.lower[k]);
        hi = std::max(hi, b.upper[k]);
      }
      for (PartBox& b : out.boxes_) {
        if (b.lower[k] == lo)
          b.lower[k] = -INFINITY;
        if (b.upper[k] == hi)
          b.upper[k] = INFINITY;
      }
    }
  } else {
    PartBox everything;
    everything.lower.fill(-INFINITY);
    everything.upper.fill(INFINITY);
    out.boxes_ = {everything};
  }
  // Neighbours: boxes that come within twice the reach of each other (a node both reach).
  const auto& mine = out.boxes_[static_cast<std::size_t>(comm.rank())];
  for (int r = 0; r < comm.size(); ++r) {
    if (r == comm.rank())
      continue;
    const auto& other = out.boxes_[static_cast<std::size_t>(r)];
    bool near = true;
    for (int d = 0; d < Dim; ++d) {
      const auto k = static_cast<std::size_t>(d);
      const double gap = 2.0 * kReachInCells * h;
      near = near && other.lower[k] <= mine.upper[k] + gap && mine.lower[k] <= other.upper[k] + gap;
    }
    if (near)
      out.neighbours_.push_back(r);
  }
  return out;
}

template class Decomposition<2>;
template class Decomposition<3>;

} // namespace talus
