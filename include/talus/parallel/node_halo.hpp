#pragma once
// The grid nodes that the points of several ranks reach, and the sums over the ranks that make
// their values whole. After a rank has gathered its own points onto its active nodes, sum()
// replaces each shared node's values by the total over the ranks that hold it, added in rank
// order: every rank then holds the same bits on that node, updates it the same way, and the
// grid is one grid again.
#include "talus/grid/active_nodes.hpp"
#include "talus/parallel/decomposition.hpp"

#include <span>
#include <vector>

namespace talus {

template <int Dim> class NodeHalo {
public:
  /// Finds, with the neighbouring ranks, which of this step's active nodes they hold as well.
  /// Collective among neighbours; call once per step, after the active nodes are known. The
  /// decomposition is the step's (a repartition replaces it between steps).
  void connect(const Decomposition<Dim>& decomposition, const ActiveNodes<Dim>& nodes);

  /// One per-node array to sum: `width` doubles per active node.
  struct Field {
    double* values;
    int width;
  };
  /// The field of a per-node array of doubles or of fixed-size vectors of doubles.
  template <class T> static Field field(std::vector<T>& per_node) {
    static_assert(sizeof(T) % sizeof(double) == 0, "a node field holds doubles only");
    return {reinterpret_cast<double*>(per_node.data()),
            static_cast<int>(sizeof(T) / sizeof(double))};
  }
  /// Sums the fields over the ranks on the shared nodes (one message per neighbour).
  void sum(std::span<const Field> fields);

  /// Whether this rank is the lowest one holding node n: a sum over nodes counts n here only
  /// then (reactions), and so counts each node once over the ranks.
  bool counts(Index n) const {
    const auto it = std::lower_bound(shared_.begin(), shared_.end(), n);
    return it == shared_.end() || *it != n ||
           lowest_[static_cast<std::size_t>(it - shared_.begin())] == decomposition_->comm().rank();
  }

  /// The lowest rank holding node n (this rank for a node no other rank holds): its owner.
  int owner(Index n) const {
    const auto it = std::lower_bound(shared_.begin(), shared_.end(), n);
    return it == shared_.end() || *it != n
               ? decomposition_->comm().rank()
               : lowest_[static_cast<std::size_t>(it - shared_.begin())];
  }

  /// The neighbours' active nodes that lie within this rank's reach, whether this rank holds
  /// them or not, with `width` values per node: a view of the grid a few cells beyond this
  /// rank's own nodes (the ghost penalty decides which faces to stabilise from it).
  struct NeighbourNodes {
    std::vector<int> rank;         ///< per received node: the neighbour that sent it
    std::vector<Index> lattice_id; ///< per received node
    std::vector<double> values;    ///< `width` per received node
  };
  /// Collective among neighbours. values: `width` per active node of connect()'s nodes.
  NeighbourNodes neighbour_nodes(const ActiveNodes<Dim>& nodes, std::span<const double> values,
                                 int width) const;

private:
  const Decomposition<Dim>* decomposition_ = nullptr;
  std::vector<int> peers_;                     ///< neighbours that share nodes this step
  std::vector<std::vector<Index>> with_peer_;  ///< per peer: shared node numbers, ascending
  std::vector<std::vector<std::size_t>> slot_; ///< per peer: their index into shared_
  std::vector<Index> shared_;                  ///< every shared node, ascending
  std::vector<int> lowest_;                    ///< per shared node: the lowest rank holding it
};

} // namespace talus
