#include "talus/solver/f_bar.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace talus {

template <int Dim> void FBarCells::build(const Grid<Dim>& grid, const Particles<Dim>& particles) {
  const auto np = static_cast<std::size_t>(particles.size());
  // Lattice cell of every point; a point exactly on the far boundary belongs to the last cell.
  std::vector<Index> lattice(np);
  for (std::size_t p = 0; p < np; ++p) {
    const std::array<Index, Dim> cell = grid.cell_of(particles.x[p]);
    Index flat = 0;
    for (int d = Dim - 1; d >= 0; --d)
      flat = flat * grid.cells(d) + cell[static_cast<std::size_t>(d)];
    lattice[p] = flat;
  }
  // Group by lattice cell (stable, so points keep their order inside a cell), then number the
  // non-empty cells consecutively.
  points_.resize(np);
  std::iota(points_.begin(), points_.end(), Index{0});
  std::stable_sort(points_.begin(), points_.end(), [&](Index a, Index b) {
    return lattice[static_cast<std::size_t>(a)] < lattice[static_cast<std::size_t>(b)];
  });
  begin_.assign(1, 0);
  cell_of_.assign(np, 0);
  weight_.assign(np, 0.0);
  for (std::size_t k = 0; k < np; ++k) {
    const auto p = static_cast<std::size_t>(points_[k]);
    if (k > 0 && lattice[p] != lattice[static_cast<std::size_t>(points_[k - 1])])
      begin_.push_back(static_cast<Index>(k));
    cell_of_[p] = static_cast<Index>(begin_.size()) - 1;
  }
  begin_.push_back(static_cast<Index>(np));
  for (Index c = 0; c < cell_count(); ++c) {
    double total = 0;
    for (Index k = begin(c); k < end(c); ++k)
      total += particles.volume[static_cast<std::size_t>(points_[static_cast<std::size_t>(k)])];
    for (Index k = begin(c); k < end(c); ++k) {
      const auto p = static_cast<std::size_t>(points_[static_cast<std::size_t>(k)]);
      weight_[p] = particles.volume[p] / total;
    }
  }
}

template void FBarCells::build<2>(const Grid<2>&, const Particles<2>&);
template void FBarCells::build<3>(const Grid<3>&, const Particles<3>&);

} // namespace talus
