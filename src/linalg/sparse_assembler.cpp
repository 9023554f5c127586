#include "talus/linalg/sparse_assembler.hpp"

#include <algorithm>
#include <stdexcept>

namespace talus {

void SparseAssembler::begin(Index size, bool new_structure) {
  recording_ = new_structure || slots_.empty() || matrix_.rows() != size;
  next_ = 0;
  if (recording_) {
    triplets_.clear();
    matrix_.resize(static_cast<Eigen::Index>(size), static_cast<Eigen::Index>(size));
  } else {
    std::fill(matrix_.valuePtr(), matrix_.valuePtr() + matrix_.nonZeros(), 0.0);
    values_ = matrix_.valuePtr();
  }
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
  slots_.resize(triplets_.size());
  for (std::size_t k = 0; k < triplets_.size(); ++k) {
    const auto& t = triplets_[k];
    const int* first = inner + outer[t.col()];
    const int* last = inner + outer[t.col() + 1];
    slots_[k] = static_cast<int>(std::lower_bound(first, last, t.row()) - inner);
  }
  triplets_.clear();
  return matrix_;
}

} // namespace talus
