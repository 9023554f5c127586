#pragma once
// Sparse assembly that pays for the structure once per connectivity. A Newton solve on a fixed
// particle-grid connectivity assembles its tangent many times with the same contributions
// arriving in the same order; only their values change. The first pass after a structure
// change records the contributions and builds the compressed (CSC) matrix from them column by
// column, remembering for every contributed entry the position of its value; every later pass
// adds the values straight into those positions, with no search and no allocation.
//
// Contributions come one entry at a time (add) or as a dense element block over a list of
// DOFs (add_block, e.g. one material point's K_p over its stencil); entries with a negative
// row or column (no unknown) are skipped. Every entry sums its contributions in the order they
// arrived, in the recording pass as in the replays, so a block adds exactly what its entries
// would and a replay equals a fresh recording bit for bit.
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
      record_entry(row, col, value);
      return;
    }
    if (next_ >= slots_.size())
      throw_overflow();
    if (const int slot = slots_[next_++]; slot >= 0)
      values_[slot] += value;
  }

  /// Adds block(i, j) at (dofs[i], dofs[j]). Throws std::invalid_argument if the block is not
  /// dofs.size() square, std::logic_error if a replayed pass runs past the recorded
  /// contributions.
  void add_block(std::span<const Index> dofs, const Eigen::Ref<const Eigen::MatrixXd>& block);

  /// Ends the pass; throws std::logic_error if a replayed pass did not bring exactly the
  /// recorded number of contributions (a caller that changed its structure without saying so).
  const SparseMatrix& finish();

  /// Whether the last finished pass recorded a new structure.
  bool recorded() const { return recorded_; }

private:
  /// A recorded contribution: its row and column DOFs (ranges of dofs_) and its values
  /// (column-major, from recorded_values_[first]; its slots start at slots_[first]).
  struct Contribution {
    std::size_t rows, cols;
    int row_count, col_count;
    std::size_t first;
  };
  struct Incidence { // a column reached by contribution k at its local column j
    int k, j;
  };

  void record_entry(Index row, Index col, double value);
  void record_dofs(std::span<const Index> dofs);
  void build_structure();
  [[noreturn]] static void throw_overflow();

  SparseMatrix matrix_;
  Index size_ = 0;
  /// Per contributed entry (in stream order): its position in the matrix's value array, -1 for
  /// a skipped entry.
  std::vector<int> slots_;
  double* values_ = nullptr;
  std::size_t next_ = 0;
  bool recording_ = true;
  bool recorded_ = true;

  // Recording pass and structure building; kept to reuse their memory.
  std::vector<Contribution> contributions_;
  std::vector<Index> dofs_;
  std::vector<double> recorded_values_;
  std::vector<int> column_start_, fill_, row_mark_, row_position_, outer_, inner_;
  std::vector<Incidence> incidence_;
  std::vector<double> values_scratch_;
};

} // namespace talus
