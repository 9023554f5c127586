#include "talus/linalg/dof_map.hpp"

#include <algorithm>
#include <fmt/format.h>
#include <stdexcept>
#include <utility>

namespace talus {

DofMap::DofMap(int share, std::vector<Index> overlap_nodes, const NodeDofs& global,
               std::span<const int> node_owner)
    : share_(share), layout_(global.layout()), nodes_(std::move(overlap_nodes)) {
  const auto node_count = static_cast<Index>(node_owner.size());
  const std::span<const Index> global_node_dofs = global.table();
  if (global.nodes() != node_count)
    throw std::invalid_argument(
        fmt::format("DofMap: unknowns of {} nodes for {} owners", global.nodes(), node_count));
  std::sort(nodes_.begin(), nodes_.end());
  nodes_.erase(std::unique(nodes_.begin(), nodes_.end()), nodes_.end());
  node_state_.assign(node_owner.size(), kOutside);
  local_dofs_.assign(global_node_dofs.size(), kNotInOverlap);
  // (global id, slot in local_dofs_) of the owned DOFs and of the ghosts, numbered below.
  std::vector<std::pair<Index, std::size_t>> owned, ghosts;
  for (const Index n : nodes_) {
    if (n < 0 || n >= node_count)
      throw std::invalid_argument(fmt::format(
          "DofMap: share {} lists node {} outside the grid's {} nodes", share, n, node_count));
    const int owner = node_owner[at(n)];
    if (owner < 0)
      throw std::invalid_argument(
          fmt::format("DofMap: node {} of share {} has no owning share", n, share));
    node_state_[at(n)] = owner == share ? kOwned : kGhost;
    const int width = layout_.width();
    for (int k = 0; k < width; ++k) {
      const std::size_t slot = at(width * n + k);
      local_dofs_[slot] = kNoDof;
      if (const Index gid = global_node_dofs[slot]; gid >= 0)
        (owner == share ? owned : ghosts).emplace_back(gid, slot);
    }
  }
  std::sort(owned.begin(), owned.end());
  std::sort(ghosts.begin(), ghosts.end());
  owned_count_ = static_cast<Index>(owned.size());
  gids_.reserve(owned.size() + ghosts.size());
  for (const auto* part : {&owned, &ghosts})
    for (const auto& [gid, slot] : *part) {
      local_dofs_[slot] = static_cast<Index>(gids_.size());
      gids_.push_back(gid);
    }
}

void DofMap::refuse_node_outside(Index node) const {
  throw std::invalid_argument(fmt::format("share {} reaches grid node {}, which is not in its DOF "
                                          "map (a ghost node is missing from its overlap)",
                                          share_, node));
}

Eigen::VectorXd DofMap::restrict_to_overlap(const Eigen::VectorXd& global) const {
  Eigen::VectorXd local(overlap_count());
  for (std::size_t l = 0; l < gids_.size(); ++l)
    local[static_cast<Eigen::Index>(l)] = global[gids_[l]];
  return local;
}

void DofMap::add_to_global(const Eigen::VectorXd& local, Eigen::VectorXd& global) const {
  for (std::size_t l = 0; l < gids_.size(); ++l)
    global[gids_[l]] += local[static_cast<Eigen::Index>(l)];
}

SparseMatrix remapped(const SparseMatrix& K, std::span<const Index> to, Index size) {
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(static_cast<std::size_t>(K.nonZeros()));
  for (int col = 0; col < K.outerSize(); ++col)
    for (SparseMatrix::InnerIterator it(K, col); it; ++it)
      entries.emplace_back(static_cast<int>(to[at(it.row())]), static_cast<int>(to[at(it.col())]),
                           it.value());
  SparseMatrix out(size, size);
  out.setFromTriplets(entries.begin(), entries.end());
  return out;
}

void DofMap::add_to_global(const SparseMatrix& local, SparseMatrix& global) const {
  global += remapped(local, gids_, global.rows());
}

} // namespace talus
