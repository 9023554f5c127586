#include "talus/linalg/sparse_assembler.hpp"

#include <algorithm>
#include <fmt/format.h>
#include <limits>
#include <stdexcept>

namespace talus {

namespace {
std::size_t at(Index i) {
  return static_cast<std::size_t>(i);
}
} // namespace

void SparseAssembler::begin(Index size, bool new_structure) {
  recording_ = new_structure || slots_.empty() || size_ != size;
  size_ = size;
  next_ = 0;
  if (recording_) {
    contributions_.clear();
    dofs_.clear();
    recorded_values_.clear();
  } else {
    std::fill(matrix_.valuePtr(), matrix_.valuePtr() + matrix_.nonZeros(), 0.0);
    values_ = matrix_.valuePtr();
  }
}

void SparseAssembler::throw_overflow() {
  throw std::logic_error("SparseAssembler: a replayed pass brought more contributions than the "
                         "recorded one");
}

void SparseAssembler::record_dofs(std::span<const Index> dofs) {
  for (const Index dof : dofs)
    if (dof >= size_)
      throw std::out_of_range(
          fmt::format("SparseAssembler: DOF {} in a {}x{} matrix", dof, size_, size_));
  dofs_.insert(dofs_.end(), dofs.begin(), dofs.end());
}

void SparseAssembler::record_entry(Index row, Index col, double value) {
  const Index pair[] = {row, col};
  const std::size_t first_dof = dofs_.size();
  record_dofs(pair); // validates before anything else is recorded
  contributions_.push_back({first_dof, first_dof + 1, 1, 1, recorded_values_.size()});
  recorded_values_.push_back(value);
}

void SparseAssembler::add_block(std::span<const Index> dofs,
                                const Eigen::Ref<const Eigen::MatrixXd>& block) {
  const auto n = static_cast<Eigen::Index>(dofs.size());
  if (block.rows() != n || block.cols() != n)
    throw std::invalid_argument(
        fmt::format("SparseAssembler: a {}x{} block for {} DOFs", block.rows(), block.cols(), n));
  const auto entries = static_cast<std::size_t>(n * n);
  if (recording_) {
    const std::size_t first_dof = dofs_.size();
    record_dofs(dofs);
    contributions_.push_back(
        {first_dof, first_dof, static_cast<int>(n), static_cast<int>(n), recorded_values_.size()});
    for (Eigen::Index j = 0; j < n; ++j)
      recorded_values_.insert(recorded_values_.end(), block.col(j).data(), block.col(j).data() + n);
    return;
  }
  if (slots_.size() - next_ < entries)
    throw_overflow();
  const int* slot = slots_.data() + next_;
  for (Eigen::Index j = 0; j < n; ++j)
    for (Eigen::Index i = 0; i < n; ++i, ++slot)
      if (*slot >= 0)
        values_[*slot] += block(i, j);
  next_ += entries;
}

// The matrix from the recorded contributions, one column at a time: the distinct rows that
// reach it (found with a marker per row, then sorted) and, for every contributed entry, its
// position in the value array. The recorded values are then added in stream order, as a
// replay adds them.
void SparseAssembler::build_structure() {
  // Slots and the matrix's indices are ints.
  if (recorded_values_.size() >= static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw std::length_error("SparseAssembler: more contributions than an int can count");
  const auto n = at(size_);
  const Index* dofs = dofs_.data();
  // Column -> the (contribution, local column) pairs that reach it, in stream order.
  column_start_.assign(n + 1, 0);
  for (const Contribution& c : contributions_)
    for (int j = 0; j < c.col_count; ++j)
      if (const Index col = dofs[c.cols + at(j)]; col >= 0)
        ++column_start_[at(col) + 1];
  for (std::size_t col = 0; col < n; ++col)
    column_start_[col + 1] += column_start_[col];
  incidence_.resize(at(column_start_[n]));
  fill_.assign(column_start_.begin(), column_start_.end() - 1);
  for (std::size_t k = 0; k < contributions_.size(); ++k) {
    const Contribution& c = contributions_[k];
    for (int j = 0; j < c.col_count; ++j)
      if (const Index col = dofs[c.cols + at(j)]; col >= 0)
        incidence_[at(fill_[at(col)]++)] = {static_cast<int>(k), j};
  }

  slots_.assign(recorded_values_.size(), -1);
  row_mark_.assign(n, -1);
  row_position_.resize(n);
  outer_.assign(n + 1, 0);
  inner_.clear();
  int* slots = slots_.data();
  int* mark = row_mark_.data();
  int* position = row_position_.data();
  for (std::size_t col = 0; col < n; ++col) {
    const auto first = inner_.size();
    const auto column = static_cast<int>(col);
    const Incidence* begin = incidence_.data() + column_start_[col];
    const Incidence* end = incidence_.data() + column_start_[col + 1];
    for (const Incidence* it = begin; it != end; ++it) {
      const Contribution& c = contributions_[at(it->k)];
      for (int i = 0; i < c.row_count; ++i)
        if (const Index row = dofs[c.rows + at(i)]; row >= 0 && mark[row] != column) {
          mark[row] = column;
          inner_.push_back(static_cast<int>(row));
        }
    }
    std::sort(inner_.begin() + static_cast<std::ptrdiff_t>(first), inner_.end());
    for (std::size_t e = first; e < inner_.size(); ++e)
      position[inner_[e]] = static_cast<int>(e);
    for (const Incidence* it = begin; it != end; ++it) {
      const Contribution& c = contributions_[at(it->k)];
      int* entry_slots = slots + c.first + at(it->j) * at(c.row_count);
      for (int i = 0; i < c.row_count; ++i)
        if (const Index row = dofs[c.rows + at(i)]; row >= 0)
          entry_slots[i] = position[row];
    }
    outer_[col + 1] = static_cast<int>(inner_.size());
  }
  values_scratch_.assign(inner_.size(), 0.0);
  for (std::size_t e = 0; e < recorded_values_.size(); ++e)
    if (slots[e] >= 0)
      values_scratch_[at(slots[e])] += recorded_values_[e];
  matrix_ =
      Eigen::Map<const SparseMatrix>(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n),
                                     static_cast<Eigen::Index>(inner_.size()), outer_.data(),
                                     inner_.data(), values_scratch_.data());
}

const SparseMatrix& SparseAssembler::finish() {
  recorded_ = recording_;
  if (recording_)
    build_structure();
  else if (next_ != slots_.size())
    throw std::logic_error("SparseAssembler: a replayed pass brought a different number of "
                           "contributions than the recorded one");
  return matrix_;
}

} // namespace talus
