// Grid-node and smoothed particle stress (include/talus/post/stress_recovery.hpp).
//
// Why not the solver's ParticleGridMap: rebuilding its stencils, bins and active-node list
// costs about as much as a whole explicit step, and recovery needs only each particle's
// weights. So the projection is one serial scatter over the particles into node arrays over
// the box of nodes their stencils reach (serial, hence identical for any thread count) that
// keeps every particle's weights, and the smoothing a parallel loop over the particles that
// reuses them. The weights come from the solver's 1D kernels.
#include "talus/post/stress_recovery.hpp"

#include "talus/core/errors.hpp"
#include "talus/core/parallel.hpp"
#include "talus/shape/deformed_domain.hpp"
#include "talus/shape/shape_functions.hpp"

#include <algorithm>
#include <array>
#include <fmt/format.h>
#include <stdexcept>

namespace talus {

namespace {

SymmetricStress components(const Mat3& s) {
  return (SymmetricStress() << s(0, 0), s(0, 1), s(0, 2), s(1, 1), s(1, 2), s(2, 2)).finished();
}

/// The tensor-product weights of one particle: its first node and the 1D values per direction.
template <int Dim, class Shape> struct Weights {
  static constexpr int W = Shape::kWidth;
  std::array<Index, Dim> start{};
  std::array<std::array<double, W>, Dim> N{};

  Weights() = default;
  Weights(const Grid<Dim>& grid, const Particles<Dim>& particles, Index p) {
    const auto s = static_cast<std::size_t>(p);
    const Vec<Dim>& x = particles.x[s];
    if (!grid.inside(x))
      throw NumericalError(fmt::format("stress recovery: particle {} is outside the grid at "
                                       "({:g}, {:g})",
                                       p, x[0], x[1]));
    std::array<double, W> dN{};
    const Vec<Dim> lp = domain_half_widths<Dim, Shape>(particles, s);
    for (int d = 0; d < Dim; ++d) {
      const double xr = x[d] - grid.origin()[d];
      start[d] = Shape::start(xr, grid.cell_size(), lp[d], grid.cells(d));
      Shape::eval(xr, grid.cell_size(), lp[d], grid.cells(d), start[d], N[d].data(), dN.data());
    }
  }

  /// f(node's lattice coordinates, weight) for the W^Dim nodes of the stencil, x fastest.
  template <class F> void for_each_node(F&& f) const {
    std::array<int, Dim> k{};
    while (true) {
      std::array<Index, Dim> node{};
      double w = 1.0;
      for (int d = 0; d < Dim; ++d) {
        node[d] = start[d] + k[d];
        w *= N[d][static_cast<std::size_t>(k[d])];
      }
      f(node, w);
      int d = 0;
      while (d < Dim && ++k[d] == W)
        k[d++] = 0;
      if (d == Dim)
        return;
    }
  }
};

/// CPDI's weights: every node of the stencil, from the deformed voxel's corners.
template <int Dim> struct CornerWeights {
  static constexpr int W = CpdiShape::kWidth;
  typename CpdiShape::template Weights<Dim> all;
  std::array<Index, Dim> start{}; ///< all.start, named as the tensor weights name it

  CornerWeights() = default;
  CornerWeights(const Grid<Dim>& grid, const Particles<Dim>& particles, Index p) {
    const auto s = static_cast<std::size_t>(p);
    std::array<Index, Dim> cells{};
    for (int d = 0; d < Dim; ++d)
      cells[d] = grid.cells(d);
    CpdiShape::fill<Dim>(p, particles.x[s] - grid.origin(), particles.grid_F(s),
                         particles.half_size0[s], grid.cell_size(), cells, all);
    start = all.start;
  }

  template <class F> void for_each_node(F&& f) const {
    for (std::size_t k = 0; k < all.w.size(); ++k) {
      std::array<Index, Dim> node{};
      std::size_t rest = k;
      for (int d = 0; d < Dim; ++d) {
        node[d] = start[d] + static_cast<Index>(rest % W);
        rest /= W;
      }
      f(node, all.w[k]);
    }
  }
};

template <int Dim, class Shape>
using WeightsOf =
    std::conditional_t<tensor_product<Shape>(), Weights<Dim, Shape>, CornerWeights<Dim>>;

} // namespace

template <int Dim> class StressRecovery<Dim>::Impl {
public:
  virtual ~Impl() = default;
  virtual const RecoveredStress<Dim>& recover(const Particles<Dim>& particles) = 0;
};

namespace {

template <int Dim, class Shape> class RecoveryFor final : public StressRecovery<Dim>::Impl {
public:
  explicit RecoveryFor(const Grid<Dim>& grid) { out_.grid = grid; }

  const RecoveredStress<Dim>& recover(const Particles<Dim>& particles) override {
    const Grid<Dim>& grid = out_.grid;
    const auto n = static_cast<std::size_t>(particles.size());
    weights_.resize(n);
    out_.smoothed_stress.resize(n);
    std::array<Index, Dim> last{};
    for (std::size_t s = 0; s < n; ++s) {
      weights_[s] = WeightsOf<Dim, Shape>(grid, particles, static_cast<Index>(s));
      for (int d = 0; d < Dim; ++d) {
        const Index start = weights_[s].start[static_cast<std::size_t>(d)];
        out_.first[d] = s == 0 ? start : std::min(out_.first[d], start);
        last[d] = s == 0 ? start + Shape::kWidth - 1 : std::max(last[d], start + Shape::kWidth - 1);
      }
    }
    std::size_t box = n > 0 ? 1 : 0;
    for (int d = 0; d < Dim; ++d) {
      out_.count[d] = n > 0 ? last[d] - out_.first[d] + 1 : 0;
      box *= static_cast<std::size_t>(out_.count[d]);
    }
    // Sums of Phi_ip m_p sigma_p first, divided by m_i below.
    out_.node_mass.assign(box, 0.0);
    out_.node_stress.assign(box, SymmetricStress::Zero());
    for (std::size_t s = 0; s < n; ++s) {
      const double m = particles.mass[s];
      const SymmetricStress weighted = m * components(particles.stress[s]);
      weights_[s].for_each_node([&](const std::array<Index, Dim>& node, double w) {
        out_.node_mass[out_.box_index(node)] += w * m;
        out_.node_stress[out_.box_index(node)] += w * weighted;
      });
    }
    // A node inside a stencil can still get zero weight (the edge of a GIMP support).
    for (std::size_t i = 0; i < out_.node_mass.size(); ++i)
      if (out_.node_mass[i] > 0)
        out_.node_stress[i] /= out_.node_mass[i];
    parallel_for(particles.size(), [&](Index p) {
      const auto s = static_cast<std::size_t>(p);
      SymmetricStress smoothed = SymmetricStress::Zero();
      weights_[s].for_each_node([&](const std::array<Index, Dim>& node, double w) {
        smoothed += w * out_.node_stress[out_.box_index(node)];
      });
      out_.smoothed_stress[s] = smoothed;
    });
    return out_;
  }

private:
  RecoveredStress<Dim> out_;
  std::vector<WeightsOf<Dim, Shape>> weights_;
};

template <int Dim> struct RecoveryIn {
  template <class Shape> using For = RecoveryFor<Dim, Shape>;
};

} // namespace

template <int Dim>
StressRecovery<Dim>::StressRecovery(const Grid<Dim>& grid, ShapeFunction shape)
    : impl_(make_for_shape<Impl, RecoveryIn<Dim>::template For>(shape, grid)) {}
template <int Dim> StressRecovery<Dim>::~StressRecovery() = default;
template <int Dim> StressRecovery<Dim>::StressRecovery(StressRecovery&&) noexcept = default;
template <int Dim>
StressRecovery<Dim>& StressRecovery<Dim>::operator=(StressRecovery&&) noexcept = default;

template <int Dim>
const RecoveredStress<Dim>& StressRecovery<Dim>::recover(const Particles<Dim>& particles) {
  return impl_->recover(particles);
}

template class StressRecovery<2>;
template class StressRecovery<3>;

} // namespace talus
