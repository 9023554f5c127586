#pragma once
// Sparse assembly over the unknowns of a structured grid's nodes, addressed by the lattice.
//
// Why not a general assembler: a general one must either search each entry's position in its
// column or record, per contributed entry, where it goes. An MPM tangent receives one dense
// block per material point over its stencil: (Dim W^Dim)^2 entries, 324 in 2D but 6561 in 3D
// with GIMP (W = 3), so a record per entry costs hundreds of bytes per point per entry-pass
// (measured: 3.1 GB for the 3D cantilever at 8 cells through the depth, 32768 points). On a
// lattice the position of an entry follows from the two nodes' lattice offset instead: every
// column of node j holds the rows of the nodes j couples with, in a fixed order, so a table per
// node, indexed by the offset to the row node, gives where that node's rows start. Memory goes
// with the matrix (its nonzeros, and (2R + 1)^Dim ints per node, R the widest offset) and not
// with the number of contributions.
//
// Use: build() sets the structure from the sets of nodes that couple (a point's stencil, a
// ghost-penalty face, the nodes of an F-bar cell) and the unknowns each node carries (a
// NodeLayout: the displacement, and any field a case adds); begin() zeroes the values;
// add_block() (one field), add_coupling_block() (two fields), add_component_block() and
// add_diagonal() add; finish() gives the matrix (compressed column storage, rows ascending).
// Each entry sums its contributions in the order they arrive.
#include "talus/grid/active_nodes.hpp"
#include "talus/linalg/linear_solver.hpp"
#include "talus/linalg/node_layout.hpp"

#include <array>
#include <span>
#include <stdexcept>
#include <vector>

namespace talus {

template <int Dim> class LatticeAssembler {
public:
  /// Sets the structure on the step's active nodes (node numbers n index `nodes`) for the
  /// unknowns of `layout`. `size`: the number of unknowns. `dof(n, k)`: the unknown of node n's
  /// k-th component over all fields (k < layout.width()), negative for none; a node's unknowns
  /// must be consecutive and ascending in k. `for_each_clique(f)` calls
  /// f(std::span<const Index> nodes) for every set of nodes that couple with each other; it is
  /// called twice. Every field of coupled nodes couples with every other. Throws
  /// std::invalid_argument if a node's unknowns are not consecutive, std::length_error if the
  /// matrix outgrows int indices.
  template <class Dof, class Cliques>
  void build(const ActiveNodes<Dim>& nodes, const NodeLayout& layout, Index size, Dof&& dof,
             Cliques&& for_each_clique);

  /// Whether the last build() gave the same structure as the build before it.
  bool same_structure_as_before() const { return same_structure_; }
  Index size() const { return size_; }

  /// Starts a pass: every value zero.
  void begin();
  /// Adds the dense block K of one field over `nodes`: row and column c k + a belong to
  /// component a of the field of nodes[k] (c: the field's components); components without an
  /// unknown are skipped. Throws std::logic_error for a pair of nodes that build() was not told
  /// couples (or a block wider than any declared one).
  void add_block(std::span<const Index> nodes, const Eigen::Ref<const Eigen::MatrixXd>& K,
                 int field = NodeLayout::kDisplacement);
  /// Adds the block coupling two fields: row r k + a is component a of row_field at nodes[k],
  /// column c l + b component b of col_field at nodes[l] (r, c: the fields' components).
  void add_coupling_block(std::span<const Index> nodes, int row_field, int col_field,
                          const Eigen::Ref<const Eigen::MatrixXd>& K);
  /// Adds K (one row and column per node) to the entries of component a of the field of every
  /// node pair.
  void add_component_block(std::span<const Index> nodes, int a,
                           const Eigen::Ref<const Eigen::MatrixXd>& K,
                           int field = NodeLayout::kDisplacement);
  /// Adds to the diagonal entry of unknown `dof`.
  void add_diagonal(Index dof, double value);
  /// The assembled matrix (valid until the next build()).
  const SparseMatrix& finish() const { return matrix_; }

private:
  /// The slot of node n (its index among the nodes with unknowns), assigned on first sight.
  template <class Dof> int visit(Index n, Dof& dof);
  /// Adds K whose rows per node are the components [row_first, row_first + row_count) of a
  /// node's unknowns and whose columns are [col_first, col_first + col_count). kCount > 0 fixes
  /// both counts at compile time, kWidth > 0 the unknowns per node (the hot displacement
  /// blocks of a displacement-only layout, whose first component is then 0).
  template <int kCount, int kWidth>
  void add_components(std::span<const Index> nodes, int row_first, int row_count, int col_first,
                      int col_count, const Eigen::Ref<const Eigen::MatrixXd>& K);
  template <int kWidth>
  void add_component(std::span<const Index> nodes, int component,
                     const Eigen::Ref<const Eigen::MatrixXd>& K);
  /// The lattice code sum_d ijk_d P^d of node n (P = 2R + 1): two nodes' codes differ by the
  /// code of their offset, unique while every offset is within R.
  Index lattice_code(Index n) const;
  void start_structure(const ActiveNodes<Dim>& nodes, Index size);
  void widen(std::span<const Index> nodes);
  void allocate_neighbour_tables();
  void mark_pairs(std::span<const Index> nodes);
  void build_columns();
  /// The slots of a block's nodes into scratch_slots_; refuses a block wider than R.
  void gather_slots(std::span<const Index> nodes);
  /// Where the rows of the block's node k start in the columns of its node l, relative to each
  /// column's start; refuses a pair that build() was not told couples.
  int row_start(std::size_t k, std::size_t l, std::span<const Index> nodes) const;

  const ActiveNodes<Dim>* nodes_ = nullptr;
  NodeLayout layout_;
  int width_ = 0; ///< unknowns per node: the layout's width
  Index size_ = 0;
  int reach_ = 0;                 ///< R: the widest lattice offset of two coupled nodes
  Index codes_ = 1;               ///< (2R + 1)^Dim offsets per node
  Index centre_ = 0;              ///< the code of offset 0
  std::vector<int> slot_of_node_; ///< per node: its slot, -1 without unknowns, -2 unseen
  std::vector<Index> node_of_slot_;
  std::vector<Index> first_dof_;                 ///< per slot: its first unknown
  std::vector<int> component_offset_;            ///< per slot and component: dof - first_dof, or -1
  std::vector<Index> slot_code_;                 ///< per slot: lattice_code of its node
  std::vector<std::array<Index, Dim>> slot_ijk_; ///< per slot: its node's lattice coordinates
  /// per slot and offset code: row_start, -1 uncoupled (while building: the coupled slot)
  std::vector<int> neighbour_row_;
  std::vector<int> slot_of_dof_; ///< per unknown: its node's slot
  bool same_structure_ = false;
  SparseMatrix matrix_;
  std::vector<char> complete_; ///< per slot: every component has an unknown
  std::vector<int> unknowns_;  ///< per slot: its node's unknowns
  std::vector<Index> scratch_slots_;
  std::vector<int> scratch_starts_;
};

template <int Dim> template <class Dof> int LatticeAssembler<Dim>::visit(Index n, Dof& dof) {
  int& slot = slot_of_node_[at(n)];
  if (slot != -2)
    return slot;
  Index first = -1, next = -1;
  const auto offsets = component_offset_.size();
  for (int k = 0; k < width_; ++k) {
    const Index d = dof(n, k);
    component_offset_.push_back(-1);
    if (d < 0)
      continue;
    if (first < 0)
      first = next = d;
    if (d != next++)
      throw std::invalid_argument("LatticeAssembler: the unknowns of a node must be consecutive "
                                  "and ascending in the component");
    component_offset_.back() = static_cast<int>(d - first);
  }
  if (first < 0) {
    component_offset_.resize(offsets);
    return slot = -1;
  }
  slot = static_cast<int>(node_of_slot_.size());
  node_of_slot_.push_back(n);
  first_dof_.push_back(first);
  return slot;
}

template <int Dim>
template <class Dof, class Cliques>
void LatticeAssembler<Dim>::build(const ActiveNodes<Dim>& nodes, const NodeLayout& layout,
                                  Index size, Dof&& dof, Cliques&& for_each_clique) {
  layout_ = layout;
  width_ = layout.width();
  start_structure(nodes, size);
  for_each_clique([&](std::span<const Index> nodes) {
    for (const Index n : nodes)
      visit(n, dof);
    widen(nodes);
  });
  allocate_neighbour_tables();
  for_each_clique([&](std::span<const Index> nodes) { mark_pairs(nodes); });
  build_columns();
}

} // namespace talus
