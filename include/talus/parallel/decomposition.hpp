#pragma once
// How a distributed run splits the work: every rank owns a box of grid cells (Zoltan2's
// multi-jagged cuts, weighted by the points per cell) and the points whose cell centre lies in
// its box. A cell is never split between ranks, so a point's owner is a function of its cell
// alone; the boxes are the same on every rank, so any rank can name any point's owner.
#include "talus/core/particles.hpp"
#include "talus/grid/grid.hpp"
#include "talus/parallel/communicator.hpp"
#include "talus/parallel/partition_boxes.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <span>
#include <vector>

namespace talus {

template <int Dim> class Decomposition {
public:
  /// A stencil node lies within this many cell sizes of the centre of its point's cell (widest
  /// stencil: 4 nodes, plus half a cell): the reach of a rank's points beyond its box.
  static constexpr double kReachInCells = 5.0;

  /// Partitions the cells that hold the points at `positions` (this rank's share of the run's
  /// points; a cell's points may be spread over several ranks) into one box per rank of
  /// `comm`. Collective.
  static Decomposition partition(const Communicator& comm, const Grid<Dim>& grid,
                                 std::span<const Vec<Dim>> positions);

  /// Every point on rank `r` (the others own nothing): a run's whole state in one place, for a
  /// checkpoint.
  static Decomposition all_on(const Communicator& comm, const Grid<Dim>& grid, int r) {
    Decomposition out;
    out.comm_ = &comm;
    out.grid_ = grid;
    out.boxes_.resize(static_cast<std::size_t>(comm.size()));
    for (std::size_t k = 0; k < out.boxes_.size(); ++k) {
      out.boxes_[k].lower.fill(static_cast<int>(k) == r ? -INFINITY : INFINITY);
      out.boxes_[k].upper.fill(static_cast<int>(k) == r ? INFINITY : -INFINITY);
    }
    return out;
  }

  /// This process's points all its own, on one rank: a serial run's decomposition, and every
  /// rank's before a distributed run partitions the scene.
  static Decomposition single(const Grid<Dim>& grid) {
    return all_on(Communicator::self(), grid, 0);
  }

  const Communicator& comm() const { return *comm_; }
  const std::vector<PartBox>& boxes() const { return boxes_; }

  /// The rank that owns the points of the cell holding x.
  int owner(const Vec<Dim>& x) const {
    std::array<double, 3> centre{};
    const double h = grid_.cell_size();
    for (int d = 0; d < Dim; ++d) {
      // Cells clamped into the grid (and a position that is not a number to cell 0); inside,
      // truncation is the floor, and cheaper than std::floor without SSE4.1.
      const double s = (x[d] - grid_.origin()[d]) / h;
      const Index last = grid_.cells(d) - 1;
      const Index i = !(s >= 1.0)                      ? 0
                      : s >= static_cast<double>(last) ? last
                                                       : static_cast<Index>(s);
      centre[static_cast<std::size_t>(d)] = grid_.origin()[d] + (static_cast<double>(i) + 0.5) * h;
    }
    // Boxes meet on cut planes; a centre on a cut goes to the lower rank. The boxes tile all
    // space (partition), so the nearest box only answers a partition Zoltan2 left with gaps.
    for (std::size_t r = 0; r < boxes_.size(); ++r)
      if (contains(boxes_[r], centre, 0.0))
        return static_cast<int>(r);
    return nearest(centre);
  }

  /// Whether rank r's points may reach a node at x (x within its box widened by the reach).
  bool reaches(int r, const Vec<Dim>& x) const {
    std::array<double, 3> at{};
    for (int d = 0; d < Dim; ++d)
      at[static_cast<std::size_t>(d)] = x[d];
    return contains(boxes_[static_cast<std::size_t>(r)], at, kReachInCells * grid_.cell_size());
  }

  /// The other ranks whose points may share grid nodes with this rank's, ascending.
  const std::vector<int>& neighbours() const { return neighbours_; }

private:
  static bool contains(const PartBox& b, const std::array<double, 3>& x, double widen) {
    for (int d = 0; d < Dim; ++d) {
      const auto k = static_cast<std::size_t>(d);
      if (!(x[k] >= b.lower[k] - widen && x[k] <= b.upper[k] + widen))
        return false;
    }
    return true;
  }
  int nearest(const std::array<double, 3>& x) const {
    int best = 0;
    double best_distance = INFINITY;
    for (std::size_t r = 0; r < boxes_.size(); ++r) {
      double dist = 0;
      for (int d = 0; d < Dim; ++d) {
        const auto k = static_cast<std::size_t>(d);
        const double out = std::max({0.0, boxes_[r].lower[k] - x[k], x[k] - boxes_[r].upper[k]});
        dist += out * out;
      }
      if (dist < best_distance) {
        best_distance = dist;
        best = static_cast<int>(r);
      }
    }
    return best;
  }

  const Communicator* comm_ = nullptr;
  Grid<Dim> grid_;
  std::vector<PartBox> boxes_;
  std::vector<int> neighbours_;
};

} // namespace talus
