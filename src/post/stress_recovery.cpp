// Grid-node and smoothed particle stress (include/talus/post/stress_recovery.hpp).
//
// Why not the solver's ParticleGridMap: rebuilding its stencils, bins and active-node list
// costs about as much as a whole explicit step, and recovery needs only each particle's
// weights. So the projection is one serial scatter over the particles into dense node arrays
// (serial, hence identical for any thread count) that keeps every particle's weights, and the
// smoothing a parallel loop over the particles that reuses them. The weights come from the
// solver's 1D kernels.
#include "talus/post/stress_recovery.hpp"

#include "talus/core/errors.hpp"
#include "talus/core/parallel.hpp"
#include "talus/shape/shape_functions.hpp"

#include <array>
#include <fmt/format.h>
#include <stdexcept>

namespace talus {

namespace {

SymmetricStress components(const Mat3& s) {
  return (SymmetricStress() << s(0, 0), s(0, 1), s(0, 2), s(1, 1), s(1, 2), s(2, 2)).finished();
}

/// The tensor-product weights of one particle: its first node and the 1D values per direction.
template <class Shape> struct Weights {
  Index first_node = 0;
  std::array<std::array<double, Shape::kWidth>, 2> N{};

  Weights() = default;
  Weights(const Grid<2>& grid, const Particles<2>& particles, Index p) {
    const auto s = static_cast<std::size_t>(p);
    const Vec2& x = particles.x[s];
    if (!grid.inside(x))
      throw NumericalError(fmt::format("stress recovery: particle {} is outside the grid at "
                                       "({:g}, {:g})",
                                       p, x[0], x[1]));
    std::array<Index, 2> start{};
    std::array<double, Shape::kWidth> dN{};
    for (std::size_t d = 0; d < 2; ++d) {
      const double xr =
          x[static_cast<Eigen::Index>(d)] - grid.origin()[static_cast<Eigen::Index>(d)];
      const double lp = particles.half_size0[s][static_cast<Eigen::Index>(d)];
      start[d] = Shape::start(xr, grid.cell_size(), lp);
      Shape::eval(xr, grid.cell_size(), lp, start[d], N[d].data(), dN.data());
    }
    first_node = grid.node_id(start);
  }

  /// f(node_id, weight) for the Shape::kWidth^2 nodes of the stencil (node ids run x fastest).
  template <class F> void for_each_node(Index row_stride, F&& f) const {
    for (int b = 0; b < Shape::kWidth; ++b) {
      const Index row = first_node + b * row_stride;
      for (int a = 0; a < Shape::kWidth; ++a)
        f(row + a, N[0][static_cast<std::size_t>(a)] * N[1][static_cast<std::size_t>(b)]);
    }
  }
};

} // namespace

class StressRecovery::Impl {
public:
  virtual ~Impl() = default;
  virtual const RecoveredStress& recover(const Particles<2>& particles) = 0;
};

namespace {

template <class Shape> class RecoveryFor final : public StressRecovery::Impl {
public:
  explicit RecoveryFor(const Grid<2>& grid) {
    out_.grid = grid;
    const auto nodes = static_cast<std::size_t>(grid.node_count());
    out_.node_mass.resize(nodes);
    out_.node_stress.resize(nodes);
  }

  const RecoveredStress& recover(const Particles<2>& particles) override {
    const Grid<2>& grid = out_.grid;
    const Index stride = grid.nodes(0);
    const auto n = static_cast<std::size_t>(particles.size());
    weights_.resize(n);
    out_.smoothed_stress.resize(n);
    std::fill(out_.node_mass.begin(), out_.node_mass.end(), 0.0);
    // Sums of Phi_ip m_p sigma_p first, divided by m_i below.
    std::fill(out_.node_stress.begin(), out_.node_stress.end(), SymmetricStress::Zero());
    for (std::size_t s = 0; s < n; ++s) {
      weights_[s] = Weights<Shape>(grid, particles, static_cast<Index>(s));
      const double m = particles.mass[s];
      const SymmetricStress weighted = m * components(particles.stress[s]);
      weights_[s].for_each_node(stride, [&](Index node, double w) {
        out_.node_mass[static_cast<std::size_t>(node)] += w * m;
        out_.node_stress[static_cast<std::size_t>(node)] += w * weighted;
      });
    }
    // A node inside a stencil can still get zero weight (the edge of a GIMP support).
    for (std::size_t i = 0; i < out_.node_mass.size(); ++i)
      if (out_.node_mass[i] > 0)
        out_.node_stress[i] /= out_.node_mass[i];
    parallel_for(particles.size(), [&](Index p) {
      const auto s = static_cast<std::size_t>(p);
      SymmetricStress smoothed = SymmetricStress::Zero();
      weights_[s].for_each_node(stride, [&](Index node, double w) {
        smoothed += w * out_.node_stress[static_cast<std::size_t>(node)];
      });
      out_.smoothed_stress[s] = smoothed;
    });
    return out_;
  }

private:
  RecoveredStress out_;
  std::vector<Weights<Shape>> weights_;
};

} // namespace

StressRecovery::StressRecovery(const Grid<2>& grid, ShapeFunction shape)
    : impl_(make_for_shape<Impl, RecoveryFor>(shape, grid)) {}
StressRecovery::~StressRecovery() = default;
StressRecovery::StressRecovery(StressRecovery&&) noexcept = default;
StressRecovery& StressRecovery::operator=(StressRecovery&&) noexcept = default;

const RecoveredStress& StressRecovery::recover(const Particles<2>& particles) {
  return impl_->recover(particles);
}

} // namespace talus
