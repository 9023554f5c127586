#pragma once
// The structured background grid: square cells of size h over [origin, origin + extent].
// Nodes are numbered with one ghost layer on every side, so GIMP supports of particles that
// touch the boundary never index outside the arrays. Boundary conditions act on the physical
// boundary nodes only; a particle whose centre leaves the physical domain is an error.
#include "talus/core/types.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace talus {

/// The most nodes a grid may have (ghost layers included): node ids, and the sums of an id and
/// a stencil offset, must stay within 64-bit integers (2^62 = 4.6e18). The case reader refuses
/// larger grids; nothing is allocated per node of the grid, so this is the only size limit.
inline constexpr double kMaxGridNodes = 4.0e18;

template <int Dim> class Grid {
public:
  Grid() = default;
  Grid(const Vec<Dim>& origin, double cell_size, const std::array<Index, Dim>& cells)
      : origin_(origin), h_(cell_size), cells_(cells) {
    Index n = 1;
    for (int d = 0; d < Dim; ++d) {
      nodes_[d] = cells_[d] + 1 + 2 * kGhost;
      n *= nodes_[d];
    }
    node_count_ = n;
  }

  static constexpr Index kGhost = 1;

  double cell_size() const { return h_; }
  const Vec<Dim>& origin() const { return origin_; }
  Index cells(int d) const { return cells_[d]; }
  Vec<Dim> extent() const {
    Vec<Dim> e;
    for (int d = 0; d < Dim; ++d)
      e[d] = h_ * static_cast<double>(cells_[d]);
    return e;
  }
  /// Nodes along direction d including both ghost layers.
  Index nodes(int d) const { return nodes_[d]; }
  Index node_count() const { return node_count_; }

  /// Flat index of the node with physical lattice coordinates ijk (ghosts at -1 and cells+1).
  Index node_id(const std::array<Index, Dim>& ijk) const {
    Index id = 0;
    for (int d = Dim - 1; d >= 0; --d)
      id = id * nodes_[d] + (ijk[d] + kGhost);
    return id;
  }
  std::array<Index, Dim> node_ijk(Index id) const {
    std::array<Index, Dim> ijk{};
    for (int d = 0; d < Dim; ++d) {
      ijk[d] = id % nodes_[d] - kGhost;
      id /= nodes_[d];
    }
    return ijk;
  }
  Vec<Dim> node_position(const std::array<Index, Dim>& ijk) const {
    Vec<Dim> x;
    for (int d = 0; d < Dim; ++d)
      x[d] = origin_[d] + h_ * static_cast<double>(ijk[d]);
    return x;
  }
  /// The cell that holds x (clamped to the grid: a point on the far boundary is in the last
  /// cell).
  std::array<Index, Dim> cell_of(const Vec<Dim>& x) const {
    std::array<Index, Dim> cell{};
    for (int d = 0; d < Dim; ++d)
      cell[d] = std::clamp<Index>(static_cast<Index>(std::floor((x[d] - origin_[d]) / h_)), 0,
                                  cells_[d] - 1);
    return cell;
  }
  bool inside(const Vec<Dim>& x) const {
    for (int d = 0; d < Dim; ++d) {
      const double s = (x[d] - origin_[d]) / h_;
      if (!(s >= 0.0 && s <= static_cast<double>(cells_[d])))
        return false;
    }
    return true;
  }

private:
  Vec<Dim> origin_ = Vec<Dim>::Zero();
  double h_ = 1.0;
  std::array<Index, Dim> cells_{};
  std::array<Index, Dim> nodes_{};
  Index node_count_ = 0;
};

} // namespace talus
