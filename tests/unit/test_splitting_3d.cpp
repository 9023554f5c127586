// Splitting in 3D (core/splitting.hpp, Dim = 3): the talk's criterion on every diagonal and
// off-diagonal term of the 3x3 F^split, the cut across the longest deformed edge of the
// hexahedral voxel, the exact conservation of a split (halving is exact in binary floating
// point, so mass, volume, momentum and kinetic energy are compared with ==), the children
// tiling the parent's deformed hexahedron (round-off 1e-12), and a whole scene whose top
// traction follows the children.
#include "talus/io/case_reader.hpp"
#include "talus/scene/scene.hpp"
#include "talus/scene/splitting.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace talus {
namespace {

constexpr double kRoundOff = 1e-12;

Mat3 deformation() {
  Mat3 F;
  F << 1.3, 0.4, -0.1, -0.2, 0.9, 0.25, 0.15, -0.3, 1.1;
  return F;
}

Particles<3> one_point(const Mat3& F) {
  Particles<3> P;
  P.split_origin_inverse.assign(1, Mat3::Identity());
  P.split_generation.assign(1, 0);
  P.resize(1);
  P.x[0] = Vec3(0.3, 0.7, 0.2);
  P.x0[0] = Vec3(0.25, 0.5, 0.15);
  P.half_size0[0] = Vec3(0.05, 0.025, 0.04);
  P.volume0[0] = 8 * 0.05 * 0.025 * 0.04;
  P.F[0] = F;
  P.volume[0] = F.determinant() * P.volume0[0];
  P.mass[0] = 1700 * P.volume0[0];
  P.v[0] = Vec3(0.31, -1.7, 0.4);
  P.stress[0] << -1e4, 2e3, 1e3, 2e3, -3e4, -5e2, 1e3, -5e2, -1.5e4;
  P.external_force[0] = Vec3(3.0, -5.0, 1.0);
  return P;
}

TEST(Splitting3D, CriterionReadsEveryTermOfTheThreeByThree) {
  const SplitSpec spec; // alpha 2, beta 1/2, gamma 1
  EXPECT_EQ(split_mode<3>(Mat3::Identity(), spec), SplitMode::None);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      Mat3 F = Mat3::Identity();
      if (i == j) {
        F(i, i) = 2.01;
        EXPECT_EQ(split_mode<3>(F, spec), SplitMode::Stretch) << i;
        F(i, i) = 0.49;
        EXPECT_EQ(split_mode<3>(F, spec), SplitMode::Compression) << i;
        F(i, i) = 1.99;
        EXPECT_EQ(split_mode<3>(F, spec), SplitMode::None) << i;
      } else {
        F(i, j) = -1.01;
        EXPECT_EQ(split_mode<3>(F, spec), SplitMode::Shear) << i << j;
        F(i, j) = 0.99;
        EXPECT_EQ(split_mode<3>(F, spec), SplitMode::None) << i << j;
      }
    }
}

TEST(Splitting3D, TheLongestDeformedEdgeIsCut) {
  const Vec3 cube(0.5, 0.5, 0.5);
  for (int axis = 0; axis < 3; ++axis) {
    Mat3 F = Mat3::Identity();
    F(axis, axis) = 2.0;
    EXPECT_EQ(split_axis<3>(F, cube), axis);
    F = Mat3::Identity();
    F((axis + 1) % 3, axis) = 1.5; // shears the edge along `axis`
    EXPECT_EQ(split_axis<3>(F, cube), axis);
  }
  // A voxel left flat by earlier splits is cut across its long side.
  EXPECT_EQ(split_axis<3>(Mat3::Identity(), Vec3(0.25, 0.25, 0.5)), 2);
}

class SplitPoint3D : public ::testing::TestWithParam<int> {};

TEST_P(SplitPoint3D, ConservesMassVolumeMomentumAndKineticEnergyExactly) {
  const int axis = GetParam();
  Particles<3> P = one_point(deformation());
  const Particles<3> before = P;
  ASSERT_EQ(split_point(P, 0, axis), 1);
  EXPECT_EQ(P.mass[0] + P.mass[1], before.mass[0]);
  EXPECT_EQ(P.volume[0] + P.volume[1], before.volume[0]);
  EXPECT_EQ(P.volume0[0] + P.volume0[1], before.volume0[0]);
  EXPECT_EQ(P.mass[0] * P.v[0] + P.mass[1] * P.v[1], before.mass[0] * before.v[0]);
  EXPECT_EQ(0.5 * P.mass[0] * P.v[0].squaredNorm() + 0.5 * P.mass[1] * P.v[1].squaredNorm(),
            0.5 * before.mass[0] * before.v[0].squaredNorm());
  const Vec3 first_moment = P.mass[0] * P.x[0] + P.mass[1] * P.x[1];
  EXPECT_LE((first_moment - before.mass[0] * before.x[0]).norm(), kRoundOff);
  EXPECT_EQ(P.external_force[0] + P.external_force[1], before.external_force[0]);
  for (std::size_t c = 0; c < 2; ++c) {
    EXPECT_EQ(P.stress[c], before.stress[0]);
    EXPECT_EQ(P.split_generation[c], 1);
    EXPECT_LE((P.F[c] * P.split_origin_inverse[c] - Mat3::Identity()).norm(), kRoundOff);
  }
}

// Each child's eight corners lie in the parent's deformed hexahedron, and its centre is the
// centre of one half of it.
TEST_P(SplitPoint3D, ChildrenTileTheParentsDeformedHexahedron) {
  const int axis = GetParam();
  Particles<3> P = one_point(deformation());
  const Particles<3> parent = P;
  split_point(P, 0, axis);
  const Vec3 h = parent.half_size0[0];
  const Mat3 F_inv = parent.F[0].inverse();
  for (std::size_t c = 0; c < 2; ++c) {
    const Vec3 r = F_inv * (P.x[c] - parent.x[0]);
    for (int d = 0; d < 3; ++d)
      EXPECT_NEAR(std::abs(r[d]), d == axis ? 0.5 * h[d] : 0.0, kRoundOff) << d;
    for (int corner = 0; corner < 8; ++corner) {
      Vec3 sign;
      for (int d = 0; d < 3; ++d)
        sign[d] = (corner >> d) & 1 ? 1.0 : -1.0;
      const Vec3 x = P.x[c] + P.F[c] * sign.cwiseProduct(P.half_size0[c]);
      const Vec3 rc = F_inv * (x - parent.x[0]);
      for (int d = 0; d < 3; ++d)
        EXPECT_LE(std::abs(rc[d]), h[d] * (1 + kRoundOff));
    }
    for (int d = 0; d < 3; ++d)
      EXPECT_EQ(P.half_size0[c][d], d == axis ? 0.5 * h[d] : h[d]);
  }
}

INSTANTIATE_TEST_SUITE_P(EveryAxis, SplitPoint3D, ::testing::Values(0, 1, 2));

const std::string kBox = R"(name: box
dimension: 3
analysis: explicit
grid: {origin: [0, 0, 0], extent: [1, 1, 1], cell_size: 0.1}
materials:
  - {name: m, model: linear_elastic, density: 1000, youngs_modulus: 1.0e6, poisson_ratio: 0.3}
bodies:
  - {name: a, material: m, shape: box, min: [0.4, 0.4, 0.4], max: [0.6, 0.5, 0.6],
     split: {alpha: 2, beta: 0.5, gamma: 1, max_generations: 2}}
tractions:
  - {body: a, side: top, traction: [0, -100, 0]}
time: {end_time: 0.01, cfl: 0.5}
)";

// A box of 4 x 2 x 4 points stretched along z splits every point across z; the top traction,
// on faces across the cut, is shared half and half and keeps its total.
TEST(Splitting3D, ASceneSplitsEveryStretchedPointAndKeepsItsTraction) {
  Scene<3> scene = build_scene<3>(read_case_text(kBox, "box.yaml"));
  auto& P = scene.particles;
  ASSERT_EQ(P.size(), 32);
  const double mass = [&] {
    double m = 0;
    for (const double pm : P.mass)
      m += pm;
    return m;
  }();
  Vec3 traction = Vec3::Zero();
  for (const auto& load : scene.surface_loads)
    traction += load.force;
  const std::size_t loads = scene.surface_loads.size();
  for (auto& F : P.F)
    F(2, 2) = 2.5;
  EXPECT_EQ(split_material_points(scene), 32);
  EXPECT_EQ(P.size(), 64);
  double mass_after = 0;
  for (const double pm : P.mass)
    mass_after += pm;
  EXPECT_EQ(mass_after, mass);
  Vec3 traction_after = Vec3::Zero();
  for (const auto& load : scene.surface_loads)
    traction_after += load.force;
  EXPECT_EQ(traction_after, traction);
  EXPECT_EQ(scene.surface_loads.size(), 2 * loads);
  EXPECT_EQ(static_cast<Index>(scene.particles_of_material[0].size()), P.size());
}

} // namespace
} // namespace talus
