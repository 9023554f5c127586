#pragma once
// The grid nodes that carry state in one step: those some material point's stencil reaches.
// They are numbered 0 .. size() - 1 in ascending lattice id (Grid::node_id), and every per-node
// array of a step (mass, momentum, unknowns, ...) is indexed by that number. Storage therefore
// follows the material and not the grid's bounding box: a small body in a large grid allocates
// its own nodes only. The ascending order keeps every loop over the nodes, and every sum over
// them, in the order of the lattice, independent of how the points are numbered.
#include "talus/grid/grid.hpp"

#include <algorithm>
#include <array>
#include <vector>

namespace talus {

template <int Dim> class ActiveNodes {
public:
  /// `lattice_ids`: the nodes' Grid::node_id, ascending and distinct.
  void assign(const Grid<Dim>& grid, std::vector<Index> lattice_ids) {
    grid_ = grid;
    ids_ = std::move(lattice_ids);
  }
  /// assign() that hands the previous ids' storage back in `lattice_ids` (for reuse).
  void exchange(const Grid<Dim>& grid, std::vector<Index>& lattice_ids) {
    grid_ = grid;
    ids_.swap(lattice_ids);
  }

  const Grid<Dim>& grid() const { return grid_; }
  Index size() const { return static_cast<Index>(ids_.size()); }
  Index lattice_id(Index n) const { return ids_[static_cast<std::size_t>(n)]; }
  std::array<Index, Dim> ijk(Index n) const { return grid_.node_ijk(lattice_id(n)); }
  Vec<Dim> position(Index n) const { return grid_.node_position(ijk(n)); }

  /// The number of the node with lattice id `id`, -1 if it carries no state this step.
  Index find_lattice_id(Index id) const {
    const auto it = std::lower_bound(ids_.begin(), ids_.end(), id);
    return it != ids_.end() && *it == id ? static_cast<Index>(it - ids_.begin()) : -1;
  }
  /// The number of the node at lattice coordinates ijk (ghosts at -1 and cells + 1), -1 if it
  /// lies off the lattice or carries no state this step.
  Index find(const std::array<Index, Dim>& ijk) const {
    for (int d = 0; d < Dim; ++d)
      if (ijk[d] < -Grid<Dim>::kGhost || ijk[d] >= grid_.nodes(d) - Grid<Dim>::kGhost)
        return -1;
    return find_lattice_id(grid_.node_id(ijk));
  }

private:
  Grid<Dim> grid_; // a copy (a few numbers), so that a copied ActiveNodes stays valid
  std::vector<Index> ids_;
};

} // namespace talus
