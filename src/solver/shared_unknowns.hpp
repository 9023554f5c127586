#pragma once
// Unknowns of a step that move together: a platen's nodes share its normal displacement
// (docs/case-format.md, boundaries). Each node keeps its own unknown in the assembly (the lattice
// assembler's per-node blocks stay as they are); Newton solves for the reduced unknowns x_r,
// with the step's unknowns x = T x_r, T a 0/1 matrix with one entry per row. Its residual and
// tangent are then T^T R and T^T K T: a platen's row sums its nodes' forces (the loads on them
// push it), its column their stiffness. Without sharing T is the identity and nothing is copied.
#include "talus/core/types.hpp"
#include "talus/linalg/dof_map.hpp"
#include "talus/linalg/linear_solver.hpp"

#include <Eigen/Core>

#include <utility>
#include <vector>

namespace talus {

class SharedUnknowns {
public:
  /// n unknowns, each its own; then share() ties some of them.
  void reset(Index n) {
    group_.assign(at(n), -1);
    shared_ = false;
  }
  /// Ties `unknown` to every other unknown of the same group (a group per platen).
  void share(Index unknown, int group) {
    group_[at(unknown)] = group;
    shared_ = true;
  }
  /// Numbers the reduced unknowns in the order of their first step unknown; returns whether
  /// the numbering differs from the last one's (the reduced tangent's pattern then does).
  bool finish() {
    std::vector<Index> reduced(group_.size());
    std::vector<Index> group_unknown;
    Index count = 0;
    for (std::size_t i = 0; i < group_.size(); ++i) {
      const int g = group_[i];
      if (g < 0) {
        reduced[i] = count++;
        continue;
      }
      if (group_unknown.size() <= at(g))
        group_unknown.resize(at(g) + 1, -1);
      Index& r = group_unknown[at(g)];
      if (r < 0)
        r = count++;
      reduced[i] = r;
    }
    const bool changed = shared_ && reduced != reduced_;
    reduced_ = std::move(reduced);
    count_ = count;
    return changed;
  }

  bool any() const { return shared_; }
  /// The reduced unknowns (the step's when nothing is shared).
  Index size() const { return shared_ ? count_ : static_cast<Index>(group_.size()); }
  /// A step unknown of reduced unknown r (its first).
  Index first_of(Index r) const {
    if (!shared_)
      return r;
    for (std::size_t i = 0; i < reduced_.size(); ++i)
      if (reduced_[i] == r)
        return static_cast<Index>(i);
    return -1;
  }

  /// Per reduced unknown, the row of its first step unknown (a per-unknown table: positions,
  /// near-null-space vectors).
  Eigen::MatrixXd first_rows(Eigen::MatrixXd rows) const {
    if (!shared_)
      return rows;
    Eigen::MatrixXd out(count_, rows.cols());
    for (Index i = static_cast<Index>(reduced_.size()) - 1; i >= 0; --i)
      out.row(reduced_[at(i)]) = rows.row(i);
    return out;
  }

  /// x = T x_r (x_r itself when nothing is shared; otherwise valid until the next call).
  const Eigen::VectorXd& expand(const Eigen::VectorXd& x_r) {
    if (!shared_)
      return x_r;
    expanded_.resize(static_cast<Eigen::Index>(reduced_.size()));
    for (std::size_t i = 0; i < reduced_.size(); ++i)
      expanded_[static_cast<Eigen::Index>(i)] = x_r[reduced_[i]];
    return expanded_;
  }
  /// r <- T^T r, in place (untouched when nothing is shared).
  void condense(Eigen::VectorXd& r) const {
    if (!shared_)
      return;
    Eigen::VectorXd r_r = Eigen::VectorXd::Zero(count_);
    for (std::size_t i = 0; i < reduced_.size(); ++i)
      r_r[reduced_[i]] += r[static_cast<Eigen::Index>(i)];
    r = std::move(r_r);
  }
  /// T^T K T (K itself when nothing is shared; otherwise valid until the next call).
  const SparseMatrix& condense(const SparseMatrix& K) {
    if (!shared_)
      return K;
    condensed_ = remapped(K, reduced_, count_);
    return condensed_;
  }

private:
  std::vector<int> group_;     ///< per step unknown: its group, or -1
  std::vector<Index> reduced_; ///< per step unknown: its reduced unknown (with sharing)
  Index count_ = 0;
  bool shared_ = false;
  Eigen::VectorXd expanded_;
  SparseMatrix condensed_;
};

} // namespace talus
