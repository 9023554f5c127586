#pragma once
// The particle <-> grid connectivity for one step: each particle's shape-function stencil,
// particles binned by the first node of their stencil, and the list of active nodes. Both
// transfer directions are loops over this map:
//   for_each_node_of(p, f)     particle -> its W^Dim nodes    (G2P, velocity gradients)
//   for_each_particle_of(n, f) node -> the particles it sees  (P2G as a deterministic gather)
#include "talus/core/errors.hpp"
#include "talus/core/particles.hpp"
#include "talus/grid/grid.hpp"

#include <array>
#include <fmt/format.h>
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

  struct Stencil {
    std::array<Index, Dim> start;
    std::array<std::array<double, W>, Dim> N;
    std::array<std::array<double, W>, Dim> dN;
  };

  /// Recomputes stencils, bins and active nodes. Throws NumericalError naming the particle if
  /// one has left the grid.
  void update(const Grid<Dim>& grid, const Particles<Dim>& particles) {
    grid_ = &grid;
    const Index np = particles.size();
    stencils_.resize(static_cast<std::size_t>(np));
    const double h = grid.cell_size();
    for (Index p = 0; p < np; ++p) {
      const auto s = static_cast<std::size_t>(p);
      const Vec<Dim>& x = particles.x[s];
      if (!grid.inside(x))
        throw NumericalError(
            fmt::format("particle {} left the grid: position ({:g})", p, fmt::join(x, ", ")));
      Stencil& st = stencils_[s];
      for (int d = 0; d < Dim; ++d) {
        const double xr = x[d] - grid.origin()[d];
        const double lp = particles.half_size0[s][d];
        st.start[d] = Shape::start(xr, h, lp);
        Shape::eval(xr, h, lp, st.start[d], st.N[d].data(), st.dN[d].data());
      }
    }
    // Counting sort of particles by the flat id of their stencil's first node.
    const Index nn = grid.node_count();
    bin_offset_.assign(static_cast<std::size_t>(nn + 1), 0);
    for (const Stencil& st : stencils_)
      ++bin_offset_[static_cast<std::size_t>(grid.node_id(st.start) + 1)];
    for (Index n = 0; n < nn; ++n)
      bin_offset_[static_cast<std::size_t>(n + 1)] += bin_offset_[static_cast<std::size_t>(n)];
    bin_particles_.resize(static_cast<std::size_t>(np));
    std::vector<Index> fill(bin_offset_.begin(), bin_offset_.end() - 1);
    for (Index p = 0; p < np; ++p) {
      const Index b = grid.node_id(stencils_[static_cast<std::size_t>(p)].start);
      bin_particles_[static_cast<std::size_t>(fill[static_cast<std::size_t>(b)]++)] = p;
    }
    // Active nodes: every node in the stencil of a non-empty bin, in ascending id order.
    active_flag_.assign(static_cast<std::size_t>(nn), 0);
    for (Index b = 0; b < nn; ++b) {
      if (bin_offset_[static_cast<std::size_t>(b + 1)] == bin_offset_[static_cast<std::size_t>(b)])
        continue;
      const auto start = grid.node_ijk(b);
      for (int k = 0; k < kStencilSize; ++k)
        active_flag_[static_cast<std::size_t>(grid.node_id(offset(start, k)))] = 1;
    }
    active_.clear();
    for (Index n = 0; n < nn; ++n)
      if (active_flag_[static_cast<std::size_t>(n)])
        active_.push_back(n);
  }

  const std::vector<Index>& active_nodes() const { return active_; }
  const Stencil& stencil(Index p) const { return stencils_[static_cast<std::size_t>(p)]; }

  /// f(node_id, weight, gradient) for every node of particle p's stencil.
  template <class F> void for_each_node_of(Index p, F&& f) const {
    const Stencil& st = stencils_[static_cast<std::size_t>(p)];
    for (int k = 0; k < kStencilSize; ++k) {
      const auto local = digits(k);
      double w;
      Vec<Dim> grad;
      weight(st, local, w, grad);
      f(grid_->node_id(offset(st.start, k)), w, grad);
    }
  }

  /// The grid nodes of particle p's stencil, in the order for_each_node_of visits them.
  std::array<Index, kStencilSize> stencil_nodes(Index p) const {
    const Stencil& st = stencils_[static_cast<std::size_t>(p)];
    std::array<Index, kStencilSize> nodes{};
    for (int k = 0; k < kStencilSize; ++k)
      nodes[static_cast<std::size_t>(k)] = grid_->node_id(offset(st.start, k));
    return nodes;
  }

  /// f(particle, weight, gradient) for every particle whose stencil contains `node`, in a
  /// fixed order (bin by bin, particles in ascending index).
  template <class F> void for_each_particle_of(Index node, F&& f) const {
    const auto ijk = grid_->node_ijk(node);
    for (int k = 0; k < kStencilSize; ++k) {
      const auto local = digits(k);
      std::array<Index, Dim> start;
      bool valid = true;
      for (int d = 0; d < Dim; ++d) {
        start[d] = ijk[d] - local[d];
        valid = valid && start[d] >= -Grid<Dim>::kGhost;
      }
      if (!valid)
        continue;
      const auto b = static_cast<std::size_t>(grid_->node_id(start));
      for (Index q = bin_offset_[b]; q < bin_offset_[b + 1]; ++q) {
        const Index p = bin_particles_[static_cast<std::size_t>(q)];
        double w;
        Vec<Dim> grad;
        weight(stencils_[static_cast<std::size_t>(p)], local, w, grad);
        f(p, w, grad);
      }
    }
  }

private:
  static std::array<int, Dim> digits(int k) {
    std::array<int, Dim> a{};
    for (int d = 0; d < Dim; ++d) {
      a[d] = k % W;
      k /= W;
    }
    return a;
  }
  static std::array<Index, Dim> offset(const std::array<Index, Dim>& start, int k) {
    const auto a = digits(k);
    std::array<Index, Dim> ijk{};
    for (int d = 0; d < Dim; ++d)
      ijk[d] = start[d] + a[d];
    return ijk;
  }
  static void weight(const Stencil& st, const std::array<int, Dim>& a, double& w, Vec<Dim>& grad) {
    w = 1.0;
    for (int d = 0; d < Dim; ++d)
      w *= st.N[d][static_cast<std::size_t>(a[d])];
    for (int d = 0; d < Dim; ++d) {
      double g = st.dN[d][static_cast<std::size_t>(a[d])];
      for (int e = 0; e < Dim; ++e)
        if (e != d)
          g *= st.N[e][static_cast<std::size_t>(a[e])];
      grad[d] = g;
    }
  }

  const Grid<Dim>* grid_ = nullptr;
  std::vector<Stencil> stencils_;
  std::vector<Index> bin_offset_;
  std::vector<Index> bin_particles_;
  std::vector<char> active_flag_;
  std::vector<Index> active_;
};

} // namespace talus
