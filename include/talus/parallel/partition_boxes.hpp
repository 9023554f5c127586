#pragma once
// Zoltan2's multi-jagged geometric partitioner (Trilinos) as Talus uses it: weighted points in,
// one axis-aligned box per part out. Included by the Trilinos target too, hence C++17.
#include <mpi.h>

#include <array>
#include <vector>

namespace talus {

/// A part's region: the boxes tile the bounding box of the points partitioned.
struct PartBox {
  std::array<double, 3> lower{};
  std::array<double, 3> upper{};
};

/// Splits `dim`-dimensional weighted points (coordinates x0 y0 [z0] x1 ..., this rank's share)
/// into one part per rank of `comm` of nearly equal weight, with multi-jagged cuts (recursive
/// coordinate bisection generalised to several cuts per level). Returns every part's box, the
/// same on every rank. Collective.
std::vector<PartBox> partition_boxes(int dim, const std::vector<double>& coordinates,
                                     const std::vector<double>& weights, MPI_Comm comm);

} // namespace talus
