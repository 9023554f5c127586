#pragma once
// Sparse assembly that pays for the structure once per connectivity. A Newton solve on a fixed
// particle-grid connectivity assembles its tangent many times with the same contributions
// arriving in the same order; only their values change. The first pass after a structure
// change builds the matrix from triplets (sort and sum) and records, per contribution, the
// position of its entry in the compressed (CSC) matrix; every later pass adds the values
// straight into those positions, with no sorting and no allocation.
//
// Contributions come one entry at a time (add) or as a dense element block over a list of
// DOFs (add_block, e.g. one material point's K_p over its stencil), whose entries with a
// negative DOF (no unknown) are skipped; a block adds exactly what its entries would.
#include "talus/core/types.hpp"
#include "talus/linalg/linear_solver.hpp"

#include <span>
#include <vector>

namespace talus {

class SparseAssembler {
public:
  /// Starts a pass over a size x size matrix. `new_structure`: the contributions (their order,
  /// rows and columns) differ from the previous pass's and must be recorded again.
  void begin(Index size, bool new_structure);

  void add(Index row, Index col, double value) {
    if (recording_) {
      record(row, col, value);
      return;
    }
    if (next_ >= slots_.size())
      throw_overflow();
    values_[slots_[next_++]] += value;
  }

  /// Adds block(i, j) at (dofs[i], dofs[j]) for every pair of non-negative DOFs. Throws
  /// std::invalid_argument if the block is not dofs.size() square, std::logic_error if a
  /// replayed pass runs past the recorded contributions.
  void add_block(std::span<const Index> dofs, const Eigen::Ref<const Eigen::MatrixXd>& block);

  /// Ends the pass; throws std::logic_error if a replayed pass did not bring exactly the
  /// recorded number of contributions (a caller that changed its structure without saying so).
  const SparseMatrix& finish();

  /// Whether the last finished pass recorded a new structure.
  bool recorded() const { return recorded_; }

private:
  void record(Index row, Index col, double value);
  [[noreturn]] static void throw_overflow();

  SparseMatrix matrix_;
  std::vector<Eigen::Triplet<double>> triplets_;
  /// Per contribution (skipped block entries included): while recording, its triplet's index;
  /// afterwards, the index into the matrix's value array. -1 for a skipped block entry.
  std::vector<int> slots_;
  double* values_ = nullptr;
  std::size_t next_ = 0;
  bool recording_ = true;
  bool recorded_ = true;
};

} // namespace talus
