#pragma once
// Sparse assembly that pays for the structure once per connectivity. A Newton solve on a fixed
// particle-grid connectivity assembles its tangent many times with the same contributions
// arriving in the same order; only their values change. The first pass after a structure
// change builds the matrix from triplets (sort and sum) and records, per contribution, the
// position of its entry in the compressed matrix; every later pass adds the values straight
// into those positions, with no sorting and no allocation.
#include "talus/core/types.hpp"
#include "talus/linalg/linear_solver.hpp"

#include <vector>

namespace talus {

class SparseAssembler {
public:
  /// Starts a pass over a size x size matrix. `new_structure`: the contributions (their order,
  /// rows and columns) differ from the previous pass's and must be recorded again.
  void begin(Index size, bool new_structure);

  void add(Index row, Index col, double value) {
    if (recording_)
      triplets_.emplace_back(static_cast<int>(row), static_cast<int>(col), value);
    else
      values_[static_cast<std::size_t>(slots_[next_++])] += value;
  }

  /// Ends the pass; throws std::logic_error if a replayed pass did not bring exactly the
  /// recorded number of contributions (a caller that changed its structure without saying so).
  const SparseMatrix& finish();

  /// Whether the last finished pass recorded a new structure.
  bool recorded() const { return recorded_; }

private:
  SparseMatrix matrix_;
  std::vector<Eigen::Triplet<double>> triplets_;
  std::vector<int> slots_; ///< per contribution: index into the matrix's value array
  double* values_ = nullptr;
  std::size_t next_ = 0;
  bool recording_ = true;
  bool recorded_ = true;
};

} // namespace talus
