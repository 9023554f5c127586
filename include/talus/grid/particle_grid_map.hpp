#pragma once
// The particle <-> grid connectivity for one step: each particle's shape-function stencil,
// particles binned by the first node of their stencil, and the active nodes (ActiveNodes: the
// nodes some stencil reaches, numbered in lattice order; every per-node array of the step is
// indexed by that number). Both transfer directions are loops over this map:
//   for_each_node_of(p, f)     particle -> its W^Dim nodes    (G2P, velocity gradients)
//   for_each_particle_of(n, f) node -> the particles it sees  (P2G as a deterministic gather)
// The stencils are stored bin by bin ("slots": slot q holds point point_at_slot(q)), so that a
// node's gather reads them, and any per-slot array a solver builds, in one sweep of memory.
// Nothing here is sized by the grid: bins exist for the stencil starts that hold points, and
// the links between bins and nodes are kept per stencil row (W consecutive nodes along x, which
// are consecutive in the node numbering too): W^(Dim-1) numbers per bin and per node.
#include "talus/core/errors.hpp"
#include "talus/core/parallel.hpp"
#include "talus/core/particles.hpp"
#include "talus/core/radix_sort.hpp"
#include "talus/grid/active_nodes.hpp"
#include "talus/grid/grid.hpp"
#include "talus/shape/cpdi.hpp"
#include "talus/shape/deformed_domain.hpp"
#include "talus/shape/shape_functions.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <fmt/format.h>
#include <iterator>
#include <numeric>
#include <type_traits>
#include <vector>

namespace talus {

template <int Dim, class Shape> class ParticleGridMap {
public:
  static constexpr int W = Shape::kWidth;
  static constexpr int kStencilSize = [] {
    int n = 1;
    for (int d = 0; d < Dim; ++d)
      n *= W;
    return n;
  }();

  /// Tensor-product shapes keep W values and slopes per direction; CPDI keeps its weights and
  /// gradients on every node of the stencil.
  struct TensorStencil {
    std::array<Index, Dim> start;
    std::array<std::array<double, W>, Dim> N;
    std::array<std::array<double, W>, Dim> dN;
  };
  using Stencil = std::conditional_t<tensor_product<Shape>(), TensorStencil,
                                     typename CpdiShape::template Weights<Dim>>;

  /// Recomputes stencils, bins and active nodes. Throws NumericalError naming the particle if
  /// one has left the grid.
  void update(const Grid<Dim>& grid, const Particles<Dim>& particles) {
    grid_ = &grid;
    const Index np = particles.size();
    start_id_.resize(static_cast<std::size_t>(np));
    const double h = grid.cell_size();
    // The lowest-index offender is named, whatever the thread count.
    const Index outside = parallel_find_first(
        np, [&](Index p) { return !grid.inside(particles.x[static_cast<std::size_t>(p)]); });
    if (outside >= 0)
      throw NumericalError(
          fmt::format("particle {} left the grid: position ({:g})", name_of(particles, outside),
                      fmt::join(particles.x[static_cast<std::size_t>(outside)], ", ")));
    if constexpr (tensor_product<Shape>() && Shape::kDomainFollowsStretch) {
      const Index wide = parallel_find_first(np, [&](Index p) {
        return !fits_stencil(domain_half_widths<Dim, Shape>(particles, static_cast<std::size_t>(p)),
                             h);
      });
      if (wide >= 0)
        throw_domain_too_wide(
            name_of(particles, wide),
            domain_half_widths<Dim, Shape>(particles, static_cast<std::size_t>(wide)), h);
    }
    if constexpr (tensor_product<Shape>()) {
      // The first nodes, then the bins, then the values straight into their slots.
      parallel_for(np, [&](Index p) {
        const auto s = static_cast<std::size_t>(p);
        const Vec<Dim> lp = domain_half_widths<Dim, Shape>(particles, s);
        std::array<Index, Dim> start{};
        for (int d = 0; d < Dim; ++d)
          start[d] = Shape::start(particles.x[s][d] - grid.origin()[d], h, lp[d], grid.cells(d));
        start_id_[s] = grid.node_id(start);
      });
      bin_points(np);
      stencils_.resize(static_cast<std::size_t>(np));
      parallel_for(np, [&](Index q) {
        const auto s = static_cast<std::size_t>(point_at_slot(q));
        const Vec<Dim> lp = domain_half_widths<Dim, Shape>(particles, s);
        Stencil& st = stencils_[static_cast<std::size_t>(q)];
        for (int d = 0; d < Dim; ++d) {
          const double xr = particles.x[s][d] - grid.origin()[d];
          st.start[d] = Shape::start(xr, h, lp[d], grid.cells(d));
          Shape::eval(xr, h, lp[d], grid.cells(d), st.start[d], st.N[d].data(), st.dN[d].data());
        }
      });
    } else {
      // CPDI finds its first node with its weights: computed in point order, then moved.
      by_point_.resize(static_cast<std::size_t>(np));
      std::array<Index, Dim> cells{};
      for (int d = 0; d < Dim; ++d)
        cells[d] = grid.cells(d);
      parallel_for(np, [&](Index p) {
        const auto s = static_cast<std::size_t>(p);
        Shape::template fill<Dim>(p, particles.x[s] - grid.origin(), particles.grid_F(s),
                                  particles.half_size0[s], h, cells, by_point_[s]);
        start_id_[s] = grid.node_id(by_point_[s].start);
      });
      bin_points(np);
      stencils_.resize(static_cast<std::size_t>(np));
      parallel_for(np, [&](Index q) {
        stencils_[static_cast<std::size_t>(q)] =
            by_point_[static_cast<std::size_t>(point_at_slot(q))];
      });
    }
    extra_ids_.clear();
    activate_nodes();
  }

  /// Adds nodes that no point's stencil reaches to the active nodes (a distributed run's
  /// ghost-penalty faces that reach past the rank's own points), renumbering them all; the
  /// added nodes have no points. `lattice_ids`: ascending and distinct.
  void add_nodes(std::vector<Index> lattice_ids) {
    extra_ids_ = std::move(lattice_ids);
    activate_nodes();
  }

  /// The nodes that carry state this step; node numbers index every per-node array.
  const ActiveNodes<Dim>& nodes() const { return nodes_; }
  Index node_count() const { return nodes_.size(); }
  const Stencil& stencil(Index p) const { return stencils_[slot(p)]; }
  const Stencil& stencil_of_slot(Index q) const { return stencils_[static_cast<std::size_t>(q)]; }
  /// The point in slot q (slots: the points bin by bin, the order of every gather).
  Index point_at_slot(Index q) const { return bin_particles_[static_cast<std::size_t>(q)]; }

  /// f(node, weight, gradient) for every node of particle p's stencil.
  template <class F> void for_each_node_of(Index p, F&& f) const {
    visit_nodes_of<true>(static_cast<Index>(slot(p)), f);
  }
  /// The same for the point in slot q: a loop over the slots reads the stencils in order.
  template <class F> void for_each_node_of_slot(Index q, F&& f) const {
    visit_nodes_of<true>(q, f);
  }
  /// f(node, weight): for_each_node_of_slot without the gradients.
  template <class F> void for_each_node_weight_of_slot(Index q, F&& f) const {
    visit_nodes_of<false>(q, [&](Index n, double w, const Vec<Dim>&) { f(n, w); });
  }

  /// The nodes of particle p's stencil, in the order for_each_node_of visits them.
  std::array<Index, kStencilSize> stencil_nodes(Index p) const {
    const std::int32_t b = bin_of_slot_[slot(p)];
    std::array<Index, kStencilSize> nodes{};
    for (int k = 0; k < kStencilSize; ++k)
      nodes[static_cast<std::size_t>(k)] = Index{bin_rows_[row_link(b, k / W)]} + k % W;
    return nodes;
  }

  /// f(particle, weight, gradient) for every particle whose stencil contains `node`, in a
  /// fixed order (bin by bin, particles in ascending index).
  template <class F> void for_each_particle_of(Index node, F&& f) const {
    visit_particles_of<true>(
        node, [&](Index q, double w, const Vec<Dim>& grad) { f(point_at_slot(q), w, grad); });
  }
  /// f(particle, weight): for_each_particle_of without the gradients.
  template <class F> void for_each_particle_weight_of(Index node, F&& f) const {
    visit_particles_of<false>(node,
                              [&](Index q, double w, const Vec<Dim>&) { f(point_at_slot(q), w); });
  }
  /// for_each_particle_of naming each point by its slot: f(slot, weight, gradient).
  template <class F> void for_each_slot_of(Index node, F&& f) const {
    visit_particles_of<true>(node, f);
  }
  /// f(slot, weight): for_each_slot_of without the gradients.
  template <class F> void for_each_slot_weight_of(Index node, F&& f) const {
    visit_particles_of<false>(node, [&](Index q, double w, const Vec<Dim>&) { f(q, w); });
  }

private:
  template <bool kGradient, class F> void visit_nodes_of(Index q, F&& f) const {
    const Stencil& st = stencils_[static_cast<std::size_t>(q)];
    const std::int32_t b = bin_of_slot_[static_cast<std::size_t>(q)];
    for (int k = 0; k < kStencilSize; ++k) {
      const auto local = digits(k);
      double w;
      Vec<Dim> grad;
      weight<kGradient>(st, local, w, grad);
      f(Index{bin_rows_[row_link(b, k / W)]} + k % W, w, grad);
    }
  }

  /// f(slot, weight, gradient) for every point whose stencil contains `node`.
  template <bool kGradient, class F> void visit_particles_of(Index node, F&& f) const {
    const auto ijk = nodes_.ijk(node);
    const Index id = nodes_.lattice_id(node);
    for (int r = 0; r < kRows; ++r) {
      // Stencil positions k = a0 + W r: the bins whose first node is id - row_shift_[r] - a0,
      // found from the last bin at or before id - row_shift_[r] going down.
      auto local = digits(W * r);
      bool valid = true;
      for (int d = 1; d < Dim; ++d)
        valid = valid && ijk[d] - local[d] >= -Grid<Dim>::kGhost;
      if (!valid)
        continue;
      const Index base = id - row_shift_[static_cast<std::size_t>(r)];
      for (std::int32_t b = node_rows_[row_link(node, r)];
           b >= 0 && bin_start_id_[static_cast<std::size_t>(b)] > base - W; --b) {
        local[0] = static_cast<int>(base - bin_start_id_[static_cast<std::size_t>(b)]);
        if (ijk[0] - local[0] < -Grid<Dim>::kGhost)
          break;
        for (Index q = bin_offset_[static_cast<std::size_t>(b)];
             q < bin_offset_[static_cast<std::size_t>(b) + 1]; ++q) {
          double w;
          Vec<Dim> grad;
          weight<kGradient>(stencils_[static_cast<std::size_t>(q)], local, w, grad);
          f(q, w, grad);
        }
      }
    }
  }

  /// How messages name point p: its global id in a distributed run, else its index.
  static Index name_of(const Particles<Dim>& particles, Index p) {
    return particles.global_id.empty() ? p : particles.global_id[static_cast<std::size_t>(p)];
  }

  /// A domain that follows the stretch must stay within the stencil's reach.
  static bool fits_stencil(const Vec<Dim>& lp, double h) {
    for (int d = 0; d < Dim; ++d)
      if (!(lp[d] <= Shape::kMaxHalfWidthInCells * h))
        return false;
    return true;
  }
  [[noreturn]] static void throw_domain_too_wide(Index p, const Vec<Dim>& lp, double h) {
    int d = 0;
    while (d + 1 < Dim && lp[d] <= Shape::kMaxHalfWidthInCells * h)
      ++d;
    throw NumericalError(fmt::format(
        "particle {}'s {} domain is wider than its stencil reaches: half-width {:g} along "
        "axis {}, more than {:g} cell size(s) of {:g}; split stretched points (a body's "
        "'split' block) or start with more particles per cell",
        p, Shape::kName, lp[d], d, Shape::kMaxHalfWidthInCells, h));
  }

  /// Stencil rows: W^(Dim-1) lines of W nodes along x.
  static constexpr int kRows = kStencilSize / W;
  /// Index of row r of bin or node i in bin_rows_ / node_rows_.
  static std::size_t row_link(Index i, int r) {
    return static_cast<std::size_t>(i) * kRows + static_cast<std::size_t>(r);
  }
  static std::array<int, Dim> digits(int k) {
    std::array<int, Dim> a{};
    for (int d = 0; d < Dim; ++d) {
      a[d] = k % W;
      k /= W;
    }
    return a;
  }

  // The points sorted by the lattice id of their stencil's first node (ascending index within
  // a bin), one bin per distinct first node.
  void bin_points(Index np) {
    bin_particles_.resize(static_cast<std::size_t>(np));
    std::iota(bin_particles_.begin(), bin_particles_.end(), Index{0});
    radix_sort_by(
        bin_particles_, [&](Index p) { return start_id_[static_cast<std::size_t>(p)]; }, scratch_);
    bin_start_id_.clear();
    bin_offset_.clear();
    bin_of_slot_.resize(static_cast<std::size_t>(np));
    slot_of_point_.resize(static_cast<std::size_t>(np));
    for (Index q = 0; q < np; ++q) {
      const auto p = static_cast<std::size_t>(bin_particles_[static_cast<std::size_t>(q)]);
      slot_of_point_[p] = q;
      if (bin_start_id_.empty() || start_id_[p] != bin_start_id_.back()) {
        bin_start_id_.push_back(start_id_[p]);
        bin_offset_.push_back(q);
      }
      bin_of_slot_[static_cast<std::size_t>(q)] =
          static_cast<std::int32_t>(bin_start_id_.size() - 1);
    }
    bin_offset_.push_back(np);
  }

  // Active nodes: every node of a bin's stencil, in ascending lattice id: the bins' first
  // nodes dilated by the stencil one direction at a time (the union of W copies of a sorted
  // list shifted by 0 .. W-1 lattice steps is a W-way merge), in time and memory linear in the
  // active nodes. The W nodes of a stencil row are consecutive lattice ids, all active, hence
  // consecutive node numbers: a row is known by its first node.
  void activate_nodes() {
    std::vector<Index>& ids = node_ids_;
    ids.assign(bin_start_id_.begin(), bin_start_id_.end());
    Index stride = 1;
    for (int d = 0; d < Dim; ++d) {
      dilate(ids, stride, scratch_);
      ids.swap(scratch_);
      stride *= grid_->nodes(d);
    }
    if (!extra_ids_.empty()) { // nodes without points: rows of stencils stay consecutive
      scratch_.clear();
      std::set_union(ids.begin(), ids.end(), extra_ids_.begin(), extra_ids_.end(),
                     std::back_inserter(scratch_));
      ids.swap(scratch_);
    }
    for (int r = 0; r < kRows; ++r) {
      const auto local = digits(W * r);
      Index shift = 0, step = 1;
      for (int d = 0; d < Dim; ++d) {
        shift += local[static_cast<std::size_t>(d)] * step;
        step *= grid_->nodes(d);
      }
      row_shift_[static_cast<std::size_t>(r)] = shift;
    }
    // Per bin and row, the node number of the row's first node; per node and row, the last bin
    // whose first node lies at or before the node shifted back by the row (both sides ascend,
    // so each is one merge-like walk per row).
    const auto bins = bin_start_id_.size();
    bin_rows_.resize(bins * kRows);
    node_rows_.resize(ids.size() * kRows);
    for (int r = 0; r < kRows; ++r) {
      const Index shift = row_shift_[static_cast<std::size_t>(r)];
      std::size_t n = 0;
      for (std::size_t b = 0; b < bins; ++b) {
        while (ids[n] < bin_start_id_[b] + shift)
          ++n;
        bin_rows_[row_link(static_cast<Index>(b), r)] = static_cast<std::int32_t>(n);
      }
      std::int32_t last = -1;
      for (std::size_t m = 0; m < ids.size(); ++m) {
        while (static_cast<std::size_t>(last + 1) < bins &&
               bin_start_id_[static_cast<std::size_t>(last + 1)] <= ids[m] - shift)
          ++last;
        node_rows_[row_link(static_cast<Index>(m), r)] = last;
      }
    }
    nodes_.exchange(*grid_, ids); // ids keeps the previous step's storage for the next
  }

  /// out = the distinct values of {x + j stride : x in sorted, 0 <= j < W}, ascending.
  static void dilate(const std::vector<Index>& sorted, Index stride, std::vector<Index>& out) {
    out.clear();
    out.reserve(sorted.size() + (W - 1) * sorted.size() / 2);
    std::array<std::size_t, W> next{};
    while (true) {
      Index lowest = -1;
      for (int j = 0; j < W; ++j)
        if (next[static_cast<std::size_t>(j)] < sorted.size()) {
          const Index v = sorted[next[static_cast<std::size_t>(j)]] + j * stride;
          lowest = lowest < 0 ? v : std::min(lowest, v);
        }
      if (lowest < 0)
        return;
      out.push_back(lowest);
      for (int j = 0; j < W; ++j)
        if (next[static_cast<std::size_t>(j)] < sorted.size() &&
            sorted[next[static_cast<std::size_t>(j)]] + j * stride == lowest)
          ++next[static_cast<std::size_t>(j)];
    }
  }

  static int flat(const std::array<int, Dim>& a) {
    int k = 0;
    for (int d = Dim - 1; d >= 0; --d)
      k = k * W + a[d];
    return k;
  }

  /// The weight and (with kGradient) the gradient of the stencil node at offsets a from its
  /// first node.
  template <bool kGradient>
  static void weight(const Stencil& st, const std::array<int, Dim>& a, double& w, Vec<Dim>& grad) {
    if constexpr (!tensor_product<Shape>()) {
      w = st.w[static_cast<std::size_t>(flat(a))];
      if constexpr (kGradient)
        grad = st.grad[static_cast<std::size_t>(flat(a))];
    } else {
      w = 1.0;
      for (int d = 0; d < Dim; ++d)
        w *= st.N[d][static_cast<std::size_t>(a[d])];
      if constexpr (!kGradient)
        return;
      for (int d = 0; d < Dim; ++d) {
        double g = st.dN[d][static_cast<std::size_t>(a[d])];
        for (int e = 0; e < Dim; ++e)
          if (e != d)
            g *= st.N[e][static_cast<std::size_t>(a[e])];
        grad[d] = g;
      }
    }
  }

  std::size_t slot(Index p) const {
    return static_cast<std::size_t>(slot_of_point_[static_cast<std::size_t>(p)]);
  }

  const Grid<Dim>* grid_ = nullptr;
  std::vector<Stencil> by_point_;         ///< CPDI: the stencils as computed, in point order
  std::vector<Stencil> stencils_;         ///< the same, slot by slot (bin order)
  std::vector<Index> slot_of_point_;      ///< per point: its slot
  std::vector<Index> start_id_;           ///< per point: lattice id of its stencil's first node
  std::vector<Index> bin_particles_;      ///< the points, bin by bin
  std::vector<Index> bin_offset_;         ///< per bin: where its points start (one more entry)
  std::vector<Index> bin_start_id_;       ///< per bin: lattice id of its first node, ascending
  std::vector<std::int32_t> bin_of_slot_; ///< per slot: its bin
  std::array<Index, kRows> row_shift_{};  ///< lattice id offset of each stencil row's first node
  std::vector<std::int32_t> bin_rows_;    ///< per bin and row: node number of the row's first node
  std::vector<std::int32_t> node_rows_;   ///< per node and row: the last bin at or before it, -1
  std::vector<Index> scratch_, node_ids_; // reused step to step: no allocation once sized
  std::vector<Index> extra_ids_;          ///< add_nodes()' nodes, until the next update()
  ActiveNodes<Dim> nodes_;
};

} // namespace talus
