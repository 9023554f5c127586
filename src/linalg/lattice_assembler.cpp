#include "talus/linalg/lattice_assembler.hpp"

#include <algorithm>
#include <fmt/format.h>
#include <limits>

namespace talus {

template <int Dim>
void LatticeAssembler<Dim>::start_structure(const ActiveNodes<Dim>& nodes, Index size) {
  nodes_ = &nodes;
  size_ = size;
  reach_ = 0;
  slot_of_node_.assign(at(nodes.size()), -2);
  node_of_slot_.clear();
  first_dof_.clear();
  component_offset_.clear();
}

template <int Dim> void LatticeAssembler<Dim>::widen(std::span<const Index> nodes) {
  std::array<Index, Dim> lo, hi;
  lo.fill(std::numeric_limits<Index>::max());
  hi.fill(std::numeric_limits<Index>::min());
  for (const Index n : nodes) {
    const auto ijk = nodes_->ijk(n);
    for (int d = 0; d < Dim; ++d) {
      lo[d] = std::min(lo[d], ijk[d]);
      hi[d] = std::max(hi[d], ijk[d]);
    }
  }
  for (int d = 0; d < Dim && !nodes.empty(); ++d)
    reach_ = std::max(reach_, static_cast<int>(hi[d] - lo[d]));
}

template <int Dim> Index LatticeAssembler<Dim>::lattice_code(Index n) const {
  const auto ijk = nodes_->ijk(n);
  const Index P = 2 * reach_ + 1;
  Index code = 0;
  for (int d = Dim - 1; d >= 0; --d)
    code = code * P + ijk[d] + Grid<Dim>::kGhost;
  return code;
}

template <int Dim> void LatticeAssembler<Dim>::allocate_neighbour_tables() {
  const Index P = 2 * reach_ + 1;
  codes_ = 1;
  centre_ = 0;
  for (int d = 0; d < Dim; ++d) {
    centre_ += reach_ * codes_;
    codes_ *= P;
  }
  neighbour_row_.assign(node_of_slot_.size() * at(codes_), -1);
  slot_code_.resize(node_of_slot_.size());
  slot_ijk_.resize(node_of_slot_.size());
  complete_.resize(node_of_slot_.size());
  unknowns_.resize(node_of_slot_.size());
  for (std::size_t s = 0; s < node_of_slot_.size(); ++s) {
    slot_code_[s] = lattice_code(node_of_slot_[s]);
    slot_ijk_[s] = nodes_->ijk(node_of_slot_[s]);
    const auto first = component_offset_.begin() + static_cast<std::ptrdiff_t>(s * at(width_));
    unknowns_[s] =
        static_cast<int>(std::count_if(first, first + width_, [](int o) { return o >= 0; }));
    complete_[s] = unknowns_[s] == width_;
  }
}

template <int Dim> void LatticeAssembler<Dim>::mark_pairs(std::span<const Index> nodes) {
  scratch_slots_.clear();
  for (const Index n : nodes)
    if (const int s = slot_of_node_[at(n)]; s >= 0)
      scratch_slots_.push_back(s);
  for (const Index l : scratch_slots_) {
    int* row = neighbour_row_.data() + at(l) * at(codes_);
    for (const Index k : scratch_slots_)
      row[slot_code_[at(k)] - slot_code_[at(l)] + centre_] = static_cast<int>(k);
  }
}

// Per node slot l: its coupled nodes, ordered by their first unknown, and where each one's rows
// start in l's columns; then the columns in the order of the unknowns.
template <int Dim> void LatticeAssembler<Dim>::build_columns() {
  const auto slots = node_of_slot_.size();
  std::vector<Index> neighbours_begin(slots + 1, 0), neighbours;
  std::vector<int> rows_of_slot(slots, 0);
  struct Coupled {
    Index first_dof, code;
    int slot;
    bool operator<(const Coupled& o) const { return first_dof < o.first_dof; }
  };
  std::vector<Coupled> coupled;
  for (std::size_t l = 0; l < slots; ++l) {
    int* row = neighbour_row_.data() + l * at(codes_);
    coupled.clear();
    for (Index c = 0; c < codes_; ++c) {
      if (row[c] < 0)
        continue;
      const int k = row[c]; // mark_pairs left the coupled slot there
      coupled.push_back({first_dof_[at(k)], c, k});
    }
    std::sort(coupled.begin(), coupled.end());
    int position = 0;
    for (const Coupled& n : coupled) {
      row[n.code] = position;
      neighbours.push_back(n.slot);
      position += unknowns_[at(n.slot)];
    }
    rows_of_slot[l] = position;
    neighbours_begin[l + 1] = static_cast<Index>(neighbours.size());
  }

  slot_of_dof_.assign(at(size_), -1);
  for (std::size_t s = 0; s < slots; ++s)
    for (int o = 0; o < unknowns_[s]; ++o) // a node's unknowns are consecutive
      slot_of_dof_[at(first_dof_[s] + o)] = static_cast<int>(s);
  std::vector<int> outer(at(size_) + 1, 0);
  long long nonzeros = 0;
  for (Index c = 0; c < size_; ++c) {
    if (const int s = slot_of_dof_[at(c)]; s >= 0)
      nonzeros += rows_of_slot[at(s)];
    if (nonzeros > std::numeric_limits<int>::max())
      throw std::length_error(fmt::format(
          "the tangent of {} unknowns has more than {} nonzeros, the most int indices hold", size_,
          std::numeric_limits<int>::max()));
    outer[at(c) + 1] = static_cast<int>(nonzeros);
  }
  std::vector<int> inner;
  inner.reserve(static_cast<std::size_t>(nonzeros));
  for (Index c = 0; c < size_; ++c) {
    const int l = slot_of_dof_[at(c)];
    if (l < 0)
      continue;
    for (Index e = neighbours_begin[at(l)]; e < neighbours_begin[at(l) + 1]; ++e) {
      const auto k = at(neighbours[at(e)]);
      for (int o = 0; o < unknowns_[k]; ++o)
        inner.push_back(static_cast<int>(first_dof_[k] + o));
    }
  }
  same_structure_ = matrix_.rows() == size_ && matrix_.nonZeros() == nonzeros &&
                    std::equal(outer.begin(), outer.end(), matrix_.outerIndexPtr()) &&
                    std::equal(inner.begin(), inner.end(), matrix_.innerIndexPtr());
  matrix_.resize(size_, size_);
  matrix_.resizeNonZeros(static_cast<Eigen::Index>(nonzeros));
  std::copy(outer.begin(), outer.end(), matrix_.outerIndexPtr());
  std::copy(inner.begin(), inner.end(), matrix_.innerIndexPtr());
  begin();
}

template <int Dim> void LatticeAssembler<Dim>::begin() {
  std::fill(matrix_.valuePtr(), matrix_.valuePtr() + matrix_.nonZeros(), 0.0);
}

// A block whose nodes (those with unknowns) span at most R lattice steps in every direction has
// every pair's offset within R, so the offset codes cannot alias.
template <int Dim> void LatticeAssembler<Dim>::gather_slots(std::span<const Index> nodes) {
  scratch_slots_.resize(nodes.size());
  std::array<Index, Dim> lo, hi;
  lo.fill(std::numeric_limits<Index>::max());
  hi.fill(std::numeric_limits<Index>::min());
  for (std::size_t k = 0; k < nodes.size(); ++k) {
    const int s = slot_of_node_[at(nodes[k])];
    scratch_slots_[k] = s;
    if (s < 0)
      continue;
    for (int d = 0; d < Dim; ++d) {
      lo[d] = std::min(lo[d], slot_ijk_[at(s)][at(d)]);
      hi[d] = std::max(hi[d], slot_ijk_[at(s)][at(d)]);
    }
  }
  const bool any =
      std::any_of(scratch_slots_.begin(), scratch_slots_.end(), [](Index s) { return s >= 0; });
  for (int d = 0; d < Dim && any; ++d)
    if (hi[d] - lo[d] > reach_)
      throw std::logic_error(fmt::format("LatticeAssembler: a block spans {} lattice steps, "
                                         "wider than any set of nodes declared coupled ({})",
                                         hi[d] - lo[d], reach_));
}

template <int Dim>
int LatticeAssembler<Dim>::row_start(std::size_t k, std::size_t l,
                                     std::span<const Index> nodes) const {
  const Index sk = scratch_slots_[k], sl = scratch_slots_[l];
  const int start =
      neighbour_row_[at(sl) * at(codes_) + at(slot_code_[at(sk)] - slot_code_[at(sl)] + centre_)];
  if (start < 0)
    throw std::logic_error(fmt::format("LatticeAssembler: nodes {} and {} were not declared "
                                       "coupled when the structure was built",
                                       nodes[k], nodes[l]));
  return start;
}

// Per column node l: where each row node's rows start in l's columns (one table lookup per
// pair), then per component of l one column, whose entries of node k are contiguous. Each entry
// receives one term per block, so the sums keep the order in which the blocks arrive.
template <int Dim>
template <int kCount, int kWidth>
void LatticeAssembler<Dim>::add_components(std::span<const Index> nodes, int row_first,
                                           int row_count, int col_first, int col_count,
                                           const Eigen::Ref<const Eigen::MatrixXd>& K) {
  static_assert(kWidth == 0 || kWidth == kCount, "a fixed width is a one-field layout's");
  const int rows_per_node = kCount > 0 ? kCount : row_count;
  const int cols_per_node = kCount > 0 ? kCount : col_count;
  const auto width = at(kWidth > 0 ? kWidth : width_);
  if constexpr (kWidth > 0)
    row_first = col_first = 0;
  const auto m = static_cast<Eigen::Index>(nodes.size());
  if (K.rows() != rows_per_node * m || K.cols() != cols_per_node * m)
    throw std::invalid_argument(fmt::format("LatticeAssembler: a block over {} nodes must have {} "
                                            "rows and {} columns per node",
                                            m, rows_per_node, cols_per_node));
  gather_slots(nodes);
  scratch_starts_.resize(nodes.size());
  const int* outer = matrix_.outerIndexPtr();
  double* values = matrix_.valuePtr();
  for (std::size_t l = 0; l < nodes.size(); ++l) {
    const Index sl = scratch_slots_[l];
    if (sl < 0)
      continue;
    for (std::size_t k = 0; k < nodes.size(); ++k)
      scratch_starts_[k] = scratch_slots_[k] < 0 ? -1 : row_start(k, l, nodes);
    const int* ol = component_offset_.data() + at(sl) * width + at(col_first);
    for (int b = 0; b < cols_per_node; ++b) {
      if (ol[b] < 0)
        continue;
      double* column = values + outer[first_dof_[at(sl)] + ol[b]];
      const double* k_col = K.col(cols_per_node * static_cast<Eigen::Index>(l) + b).data();
      for (std::size_t k = 0; k < nodes.size(); ++k) {
        const Index sk = scratch_slots_[k];
        if (sk < 0)
          continue;
        double* rows = column + scratch_starts_[k];
        const double* terms = k_col + at(rows_per_node) * k;
        const int* ok = component_offset_.data() + at(sk) * width + at(row_first);
        if (complete_[at(sk)]) {
          for (int a = 0; a < rows_per_node; ++a)
            rows[row_first + a] += terms[a];
        } else {
          for (int a = 0; a < rows_per_node; ++a)
            if (ok[a] >= 0)
              rows[ok[a]] += terms[a];
        }
      }
    }
  }
}

template <int Dim>
void LatticeAssembler<Dim>::add_block(std::span<const Index> nodes,
                                      const Eigen::Ref<const Eigen::MatrixXd>& K, int field) {
  const int first = layout_.offset(field), count = layout_.components(field);
  if (width_ == Dim)
    add_components<Dim, Dim>(nodes, first, Dim, first, Dim, K);
  else if (count == Dim)
    add_components<Dim, 0>(nodes, first, Dim, first, Dim, K);
  else
    add_components<0, 0>(nodes, first, count, first, count, K);
}

template <int Dim>
void LatticeAssembler<Dim>::add_coupling_block(std::span<const Index> nodes, int row_field,
                                               int col_field,
                                               const Eigen::Ref<const Eigen::MatrixXd>& K) {
  add_components<0, 0>(nodes, layout_.offset(row_field), layout_.components(row_field),
                       layout_.offset(col_field), layout_.components(col_field), K);
}

// One row and column per node: the row starts are looked up only for the pairs whose
// component has unknowns at both ends (a ghost-penalty face often lacks them at one).
template <int Dim>
void LatticeAssembler<Dim>::add_component_block(std::span<const Index> nodes, int a,
                                                const Eigen::Ref<const Eigen::MatrixXd>& K,
                                                int field) {
  const auto m = static_cast<Eigen::Index>(nodes.size());
  if (K.rows() != m || K.cols() != m)
    throw std::invalid_argument("LatticeAssembler: a component block must have one row and "
                                "column per node");
  if (width_ == Dim)
    add_component<Dim>(nodes, layout_.offset(field) + a, K);
  else
    add_component<0>(nodes, layout_.offset(field) + a, K);
}

template <int Dim>
template <int kWidth>
void LatticeAssembler<Dim>::add_component(std::span<const Index> nodes, int component,
                                          const Eigen::Ref<const Eigen::MatrixXd>& K) {
  const auto width = at(kWidth > 0 ? kWidth : width_);
  const auto c = at(component);
  gather_slots(nodes);
  const int* outer = matrix_.outerIndexPtr();
  double* values = matrix_.valuePtr();
  for (std::size_t l = 0; l < nodes.size(); ++l) {
    const Index sl = scratch_slots_[l];
    if (sl < 0 || component_offset_[at(sl) * width + c] < 0)
      continue;
    double* column = values + outer[first_dof_[at(sl)] + component_offset_[at(sl) * width + c]];
    for (std::size_t k = 0; k < nodes.size(); ++k) {
      const Index sk = scratch_slots_[k];
      if (sk < 0 || component_offset_[at(sk) * width + c] < 0)
        continue;
      column[row_start(k, l, nodes) + component_offset_[at(sk) * width + c]] +=
          K(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(l));
    }
  }
}

template <int Dim> void LatticeAssembler<Dim>::add_diagonal(Index dof, double value) {
  const int s = slot_of_dof_[at(dof)];
  const int start = neighbour_row_[at(s) * at(codes_) + at(centre_)];
  matrix_.valuePtr()[matrix_.outerIndexPtr()[dof] + start + (dof - first_dof_[at(s)])] += value;
}

template class LatticeAssembler<2>;
template class LatticeAssembler<3>;

} // namespace talus
