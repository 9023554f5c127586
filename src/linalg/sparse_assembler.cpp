#include "talus/linalg/sparse_assembler.hpp"

#include <algorithm>
#include <fmt/format.h>
#include <limits>
#include <stdexcept>

namespace talus {

void SparseAssembler::begin(Index size, bool new_structure) {
  recording_ = new_structure || slots_.empty() || matrix_.rows() != size;
  next_ = 0;
  if (recording_) {
    triplets_.clear();
    slots_.clear();
    matrix_.resize(static_cast<Eigen::Index>(size), static_cast<Eigen::Index>(size));
  } else {
    std::fill(matrix_.valuePtr(), matrix_.valuePtr() + matrix_.nonZeros(), 0.0);
    values_ = matrix_.valuePtr();
  }
}

void SparseAssembler::record(Index row, Index col, double value) {
  // Slots and the matrix's indices are ints.
  if (triplets_.size() >= static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw std::length_error("SparseAssembler: more contributions than an int can count");
  slots_.push_back(static_cast<int>(triplets_.size()));
  triplets_.emplace_back(static_cast<int>(row), static_cast<int>(col), value);
}

void SparseAssembler::throw_overflow() {
  throw std::logic_error("SparseAssembler: a replayed pass brought more contributions than the "
                         "recorded one");
}

void SparseAssembler::add_block(std::span<const Index> dofs,
                                const Eigen::Ref<const Eigen::MatrixXd>& block) {
  const auto n = static_cast<Eigen::Index>(dofs.size());
  if (block.rows() != n || block.cols() != n)
    throw std::invalid_argument(
        fmt::format("SparseAssembler: a {}x{} block for {} DOFs", block.rows(), block.cols(), n));
  if (recording_) {
    for (Eigen::Index j = 0; j < n; ++j)
      for (Eigen::Index i = 0; i < n; ++i) {
        const Index row = dofs[static_cast<std::size_t>(i)];
        const Index col = dofs[static_cast<std::size_t>(j)];
        if (row >= 0 && col >= 0)
          record(row, col, block(i, j));
        else
          slots_.push_back(-1);
      }
    return;
  }
  if (slots_.size() - next_ < static_cast<std::size_t>(n * n))
    throw_overflow();
  const int* slot = slots_.data() + next_;
  for (Eigen::Index j = 0; j < n; ++j)
    for (Eigen::Index i = 0; i < n; ++i, ++slot)
      if (*slot >= 0)
        values_[*slot] += block(i, j);
  next_ += static_cast<std::size_t>(n * n);
}

const SparseMatrix& SparseAssembler::finish() {
  recorded_ = recording_;
  if (!recording_) {
    if (next_ != slots_.size())
      throw std::logic_error("SparseAssembler: a replayed pass brought a different number of "
                             "contributions than the recorded one");
    return matrix_;
  }
  matrix_.setFromTriplets(triplets_.begin(), triplets_.end());
  matrix_.makeCompressed();
  // Column-major: the entry (row, col) sits in column col's sorted run of row indices.
  const int* outer = matrix_.outerIndexPtr();
  const int* inner = matrix_.innerIndexPtr();
  for (int& slot : slots_) {
    if (slot < 0)
      continue;
    const auto& t = triplets_[static_cast<std::size_t>(slot)];
    const int* first = inner + outer[t.col()];
    const int* last = inner + outer[t.col() + 1];
    slot = static_cast<int>(std::lower_bound(first, last, t.row()) - inner);
  }
  triplets_.clear();
  return matrix_;
}

} // namespace talus
