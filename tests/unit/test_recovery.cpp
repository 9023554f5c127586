// Stress recovery (Andersen 2013): grid-node stress sigma_i = sum_p sigma_p Phi_ip m_p / m_i and
// smoothed particle stress sigma_p^s = sum_i sigma_i Phi_ip, for linear hats and uGIMP. The
// truths checked follow from the formulas and the shape functions' properties:
//  * partition of unity (sum_i Phi_ip = 1): a uniform stress comes back exactly, and the
//    mass-weighted stress sum_i m_i sigma_i equals sum_p m_p sigma_p;
//  * the node value is a mass-weighted mean: heavier points count more;
//  * on a uniform lattice the projection is exact for linear fields at nodes whose support is
//    filled symmetrically, and both kernels interpolate linear nodal fields exactly.
// Tolerances are round-off: sums of at most ~20 terms of order 1.
#include "talus/post/stress_recovery.hpp"

#include <gtest/gtest.h>

#include <random>

namespace talus {
namespace {

constexpr double kRoundOff = 1e-12;

/// The full tensor of a recovered stress (stored as xx, xy, xz, yy, yz, zz).
Mat3 full(const SymmetricStress& c) {
  return (Mat3() << c[0], c[1], c[2], c[1], c[3], c[4], c[2], c[4], c[5]).finished();
}

/// 10 x 10 cells of size 0.1 from (-0.5, -0.2).
Grid<2> make_grid() {
  return Grid<2>(Vec2(-0.5, -0.2), 0.1, {10, 10});
}

/// Points of a regular lattice, `per_cell` per cell and direction, over the cells [i0, i1) x
/// [j0, j1), all of mass `mass`.
Particles<2> lattice(const Grid<2>& grid, int per_cell, Index i0, Index i1, Index j0, Index j1,
                     double mass = 1.0) {
  Particles<2> p;
  const double spacing = grid.cell_size() / per_cell;
  for (Index j = j0 * per_cell; j < j1 * per_cell; ++j)
    for (Index i = i0 * per_cell; i < i1 * per_cell; ++i) {
      const Index k = p.size();
      p.resize(k + 1);
      const auto s = static_cast<std::size_t>(k);
      p.x[s] = grid.origin() +
               spacing * Vec2(static_cast<double>(i) + 0.5, static_cast<double>(j) + 0.5);
      p.x0[s] = p.x[s];
      p.half_size0[s] = Vec2::Constant(0.5 * spacing);
      p.mass[s] = mass;
      p.volume0[s] = p.volume[s] = spacing * spacing;
    }
  return p;
}

/// A symmetric stress with every component set (plane strain keeps sigma_zz; xz, yz too).
Mat3 some_stress(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Mat3 s;
  for (int a = 0; a < 3; ++a)
    for (int b = a; b < 3; ++b)
      s(a, b) = s(b, a) = u(rng);
  return s;
}

class RecoveryForShape : public ::testing::TestWithParam<ShapeFunction> {};

TEST_P(RecoveryForShape, UniformStressComesBackExactly) {
  const Grid<2> grid = make_grid();
  Particles<2> p = lattice(grid, 2, 2, 7, 3, 6);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-0.02, 0.02), mass(0.5, 2.0);
  const Mat3 sigma = some_stress(rng);
  for (std::size_t s = 0; s < p.x.size(); ++s) {
    p.x[s] += Vec2(jitter(rng), jitter(rng)); // irregular positions and masses
    p.mass[s] = mass(rng);
    p.stress[s] = sigma;
  }
  StressRecovery<2> recovery(grid, GetParam());
  const RecoveredStress<2>& r = recovery.recover(p);
  Index nodes_with_mass = 0;
  for (std::size_t n = 0; n < r.node_mass.size(); ++n) {
    if (r.node_mass[n] == 0) {
      EXPECT_EQ(full(r.node_stress[n]), Mat3::Zero());
      continue;
    }
    ++nodes_with_mass;
    EXPECT_LE((full(r.node_stress[n]) - sigma).cwiseAbs().maxCoeff(), kRoundOff) << "node " << n;
  }
  EXPECT_GE(nodes_with_mass, 6 * 4); // at least the nodes of the 5 x 3 filled cells
  for (const SymmetricStress& s : r.smoothed_stress)
    EXPECT_LE((full(s) - sigma).cwiseAbs().maxCoeff(), kRoundOff);
}

TEST_P(RecoveryForShape, MassWeightedStressIsConserved) {
  // sum_i m_i sigma_i = sum_i sum_p Phi_ip m_p sigma_p = sum_p m_p sigma_p.
  const Grid<2> grid = make_grid();
  Particles<2> p = lattice(grid, 3, 1, 8, 2, 7);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> jitter(-0.01, 0.01), mass(0.1, 3.0);
  Mat3 particle_sum = Mat3::Zero();
  double scale = 0;
  for (std::size_t s = 0; s < p.x.size(); ++s) {
    p.x[s] += Vec2(jitter(rng), jitter(rng));
    p.mass[s] = mass(rng);
    p.stress[s] = some_stress(rng);
    particle_sum += p.mass[s] * p.stress[s];
    scale += p.mass[s] * p.stress[s].cwiseAbs().maxCoeff();
  }
  StressRecovery<2> recovery(grid, GetParam());
  const RecoveredStress<2>& r = recovery.recover(p);
  Mat3 node_sum = Mat3::Zero();
  for (std::size_t n = 0; n < r.node_mass.size(); ++n)
    node_sum += r.node_mass[n] * full(r.node_stress[n]);
  EXPECT_LE((node_sum - particle_sum).cwiseAbs().maxCoeff(), kRoundOff * scale);
}

TEST_P(RecoveryForShape, HeavierPointsCountMore) {
  // Two points at the same place share every weight, so each node gets the mass-weighted mean
  // (3 * 1 + 1 * 5) / 4 = 2, not the plain mean 3.
  const Grid<2> grid = make_grid();
  Particles<2> p = lattice(grid, 1, 4, 5, 4, 5);
  p.resize(2);
  p.x[1] = p.x[0];
  p.x0[1] = p.x0[0];
  p.half_size0[1] = p.half_size0[0];
  p.mass[0] = 3.0;
  p.mass[1] = 1.0;
  p.stress[0] = Mat3::Identity();
  p.stress[1] = 5.0 * Mat3::Identity();
  StressRecovery<2> recovery(grid, GetParam());
  const RecoveredStress<2>& r = recovery.recover(p);
  for (std::size_t n = 0; n < r.node_mass.size(); ++n) {
    if (r.node_mass[n] > 0) {
      EXPECT_NEAR(full(r.node_stress[n])(0, 0), 2.0, kRoundOff);
    }
  }
  EXPECT_NEAR(full(r.smoothed_stress[0])(1, 1), 2.0, kRoundOff);
  EXPECT_NEAR(full(r.smoothed_stress[1])(2, 2), 2.0, kRoundOff);
}

TEST_P(RecoveryForShape, LinearFieldIsExactInsideAUniformLattice) {
  // Equal masses on a regular lattice: around a node whose whole support is filled, the points
  // sit symmetrically, so sum_p Phi_ip m_p (x_p - x_i) = 0 and a linear field projects exactly;
  // both kernels reproduce linear nodal fields at the points.
  const Grid<2> grid = make_grid();
  Particles<2> p = lattice(grid, 2, 1, 9, 1, 9);
  auto field = [](const Vec2& x) { return 0.3 + 2.0 * x.x() - 1.5 * x.y(); };
  for (std::size_t s = 0; s < p.x.size(); ++s)
    p.stress[s] = field(p.x[s]) * Mat3::Identity();
  StressRecovery<2> recovery(grid, GetParam());
  const RecoveredStress<2>& r = recovery.recover(p);
  // Nodes 2..8 are at least one cell plus a GIMP half-width inside the filled cells 1..9.
  for (Index j = 2; j <= 8; ++j)
    for (Index i = 2; i <= 8; ++i) {
      const std::size_t n = r.box_index({i, j});
      EXPECT_NEAR(full(r.node_stress[n])(0, 0), field(grid.node_position({i, j})), kRoundOff)
          << "node " << i << ", " << j;
    }
  // Points whose stencil nodes are all among those nodes: at least half a cell inside them.
  for (std::size_t s = 0; s < p.x.size(); ++s) {
    const Vec2 rel = p.x[s] - grid.origin();
    const double h = grid.cell_size();
    if (rel.minCoeff() < 2.5 * h || rel.maxCoeff() > 7.5 * h)
      continue;
    EXPECT_NEAR(full(r.smoothed_stress[s])(1, 1), field(p.x[s]), kRoundOff) << "point " << s;
  }
}

INSTANTIATE_TEST_SUITE_P(Shapes, RecoveryForShape,
                         ::testing::Values(ShapeFunction::Linear, ShapeFunction::Gimp),
                         [](const auto& info) {
                           return info.param == ShapeFunction::Linear ? "Linear" : "Gimp";
                         });

} // namespace
} // namespace talus
