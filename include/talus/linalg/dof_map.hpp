#pragma once
// The degrees of freedom one share (one process assembling its own material points) works on:
// the overlapping node set (every grid node its contributions reach), which of those nodes it
// owns (each node is owned by exactly one share), the global id of every DOF, and the local
// numbering of the share's DOFs. Local ids run over the owned DOFs first, then the ghosts (DOFs
// of overlap nodes that other shares own), each part in ascending global id; a share that owns
// every node therefore numbers its DOFs exactly as the global numbering.
//
// It holds what a distributed assembly hands to Tpetra: a row Map from owned_gids(), an overlap
// Map from overlap_gids() (owned first, as Tpetra prefers), the share's residual and tangent
// assembled on the overlap Map in local ids, and an Export with ADD onto the row Map, which is
// what add_to_global() does on one process.
#include "talus/core/types.hpp"
#include "talus/linalg/linear_solver.hpp"
#include "talus/linalg/node_layout.hpp"

#include <span>
#include <vector>

namespace talus {

/// K with entry (i, j) moved to (to[i], to[j]) of a size x size matrix, entries that meet
/// summed (a share's matrix onto global ids, shared unknowns onto their reduced one).
SparseMatrix remapped(const SparseMatrix& K, std::span<const Index> to, Index size);

class DofMap {
public:
  /// local_dof() of a component without an unknown (held, prescribed or massless node).
  static constexpr Index kNoDof = -1;
  /// local_dof() of a node outside the share's overlap set.
  static constexpr Index kNotInOverlap = -2;

  DofMap() = default;
  /// share: this share's index. overlap_nodes: the grid nodes its contributions reach (any
  /// order, repeats allowed). global: the global unknowns of every grid node's components.
  /// node_owner[n]: the share that owns grid node n (negative: no share reaches it). Throws
  /// std::invalid_argument for a node outside the grid or an overlap node without an owner.
  DofMap(int share, std::vector<Index> overlap_nodes, const NodeDofs& global,
         std::span<const int> node_owner);

  int share() const { return share_; }
  const NodeLayout& layout() const { return layout_; }
  /// The overlap nodes, ascending.
  const std::vector<Index>& overlap_nodes() const { return nodes_; }
  bool in_overlap(Index node) const { return node_state_[at(node)] != kOutside; }
  bool owns_node(Index node) const { return node_state_[at(node)] == kOwned; }
  /// Local id of component c of the field of grid node n, kNoDof or kNotInOverlap.
  Index local_dof(Index node, int field, int c) const {
    return local_dofs_[layout_.slot(node, field, c)];
  }
  /// Local id of grid node n's k-th component over all fields, kNoDof or kNotInOverlap.
  Index local_dof_at(Index node, int k) const {
    return local_dofs_[at(node) * at(layout_.width()) + at(k)];
  }
  /// local_dof_at() of a node the share's contributions reach: throws std::invalid_argument
  /// for a node outside the overlap (a ghost node missing from it).
  Index overlap_dof_at(Index node, int k) const {
    const Index dof = local_dof_at(node, k);
    if (dof == kNotInOverlap)
      refuse_node_outside(node);
    return dof;
  }

  Index owned_count() const { return owned_count_; }
  Index overlap_count() const { return static_cast<Index>(gids_.size()); }
  /// Global ids of the owned DOFs, ascending: the local ids [0, owned_count()).
  std::span<const Index> owned_gids() const { return {gids_.data(), at(owned_count_)}; }
  /// Global id of every local DOF: the owned ones, then the ghosts.
  const std::vector<Index>& overlap_gids() const { return gids_; }

  /// The overlap's part of a global vector, in local ids (an Import).
  Eigen::VectorXd restrict_to_overlap(const Eigen::VectorXd& global) const;
  /// global[gid(l)] += local[l] for every local DOF l (an Export with ADD).
  void add_to_global(const Eigen::VectorXd& local, Eigen::VectorXd& global) const;
  /// The same for a matrix on the overlap DOFs: global(gid(i), gid(j)) += local(i, j).
  void add_to_global(const SparseMatrix& local, SparseMatrix& global) const;

private:
  [[noreturn]] void refuse_node_outside(Index node) const;

  enum NodeState : char { kOutside, kGhost, kOwned };

  int share_ = 0;
  NodeLayout layout_;
  std::vector<Index> nodes_;
  std::vector<NodeState> node_state_; ///< per grid node
  std::vector<Index> local_dofs_;     ///< per (grid node, component over all fields)
  std::vector<Index> gids_;           ///< per local DOF
  Index owned_count_ = 0;
};

} // namespace talus
