#pragma once
// What unknowns a grid node carries, and their numbering in a step.
//
// A layout lists fields of a few components each: the displacement's Dim components first, then
// what a case adds (a pore pressure's one, a body's own velocity's Dim). A node's unknowns are
// its fields' components in that order, consecutive, so the solvers see the block structure
// (node by node, field by field) that a block preconditioner splits. NodeDofs numbers them for
// one step: every assembly site asks dof(node, field, component), never Dim * node + a.
#include "talus/core/types.hpp"

#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace talus {

class NodeLayout {
public:
  /// The field every layout starts with.
  static constexpr int kDisplacement = 0;

  /// The displacement's `dim` components alone.
  explicit NodeLayout(int dim = 1) { add_field("displacement", dim); }

  /// Appends a field of `components` unknowns per node; returns its index.
  int add_field(std::string name, int components) {
    if (components <= 0)
      throw std::invalid_argument("NodeLayout: a field needs at least one component");
    names_.push_back(std::move(name));
    offsets_.push_back(width_);
    components_.push_back(components);
    width_ += components;
    return fields() - 1;
  }

  int fields() const { return static_cast<int>(names_.size()); }
  /// Unknowns per node: the components of every field.
  int width() const { return width_; }
  const std::string& name(int field) const { return names_[at(field)]; }
  /// Where the field's components start among a node's.
  int offset(int field) const { return offsets_[at(field)]; }
  int components(int field) const { return components_[at(field)]; }
  /// The field of that name, or -1.
  int find(std::string_view name) const {
    for (int f = 0; f < fields(); ++f)
      if (names_[at(f)] == name)
        return f;
    return -1;
  }
  /// The entry of (node, field, component) in a table of width() entries per node.
  std::size_t slot(Index node, int field, int c) const {
    return at(node) * at(width_) + at(offset(field) + c);
  }

private:
  std::vector<std::string> names_;
  std::vector<int> offsets_, components_;
  int width_ = 0;
};

/// The unknowns of a step's nodes under a layout: per (node, field, component) its number, or
/// a negative value for a component without one (held, prescribed, a node without mass).
class NodeDofs {
public:
  static constexpr Index kNone = -1;

  NodeDofs() = default;
  explicit NodeDofs(NodeLayout layout) : layout_(std::move(layout)) {}

  const NodeLayout& layout() const { return layout_; }
  /// Every component of `nodes` nodes without an unknown.
  void reset(Index nodes) { table_.assign(at(nodes) * at(layout_.width()), kNone); }
  Index nodes() const { return static_cast<Index>(table_.size()) / layout_.width(); }

  Index dof(Index node, int field, int c) const { return table_[layout_.slot(node, field, c)]; }
  void set(Index node, int field, int c, Index dof) { table_[layout_.slot(node, field, c)] = dof; }
  /// The unknown of a node's k-th component over all fields (k < layout().width()).
  Index dof(Index node, int k) const { return table_[at(node) * at(layout_.width()) + at(k)]; }
  /// The whole table, width() entries per node.
  std::span<const Index> table() const { return table_; }

private:
  NodeLayout layout_;
  std::vector<Index> table_;
};

} // namespace talus
