// Material-point splitting (core/splitting.hpp): the criterion and the split direction of the
// talk's six modes, the conservation of a split (mass, volume, linear momentum and kinetic
// energy exactly; halving is exact in binary floating point, so these sums are compared with
// ==), the children's place inside the parent's deformed voxel (round-off of a few operations
// on numbers of order 1: 1e-12), the copied state and history, the generation and size limits,
// bodies without a split block, tractions on split points, and whole runs: a scene in which no
// point meets the criterion gives bitwise the same results, and explicit and implicit-dynamic
// runs that do split keep their mass.
#include "talus/io/case_reader.hpp"
#include "talus/io/csv.hpp"
#include "talus/io/results.hpp"
#include "talus/material/material.hpp"
#include "talus/scene/splitting.hpp"
#include "talus/solver/explicit_solver.hpp"
#include "talus/solver/run.hpp"
#include "temporary_directory.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

namespace talus {
namespace {

namespace fs = std::filesystem;
constexpr double kRoundOff = 1e-12;

Mat2 mat(double a, double b, double c, double d) {
  Mat2 m;
  m << a, b, c, d;
  return m;
}

// One point of a splitting body with every optional block allocated, deformed by F.
Particles<2> one_point(const Mat2& F) {
  Particles<2> P;
  P.affine_velocity.assign(1, Mat2::Zero());
  P.acceleration.assign(1, Vec2::Zero());
  P.split_origin_inverse.assign(1, Mat3::Identity());
  P.split_generation.assign(1, 0);
  P.resize(1);
  P.x[0] = Vec2(0.3, 0.7);
  P.x0[0] = Vec2(0.25, 0.5);
  P.half_size0[0] = Vec2(0.05, 0.025);
  P.volume0[0] = 4 * 0.05 * 0.025;
  P.F[0] = embedded<2>(F);
  P.volume[0] = F.determinant() * P.volume0[0];
  P.mass[0] = 1700 * P.volume0[0];
  P.v[0] = Vec2(0.31, -1.7);
  P.affine_velocity[0] = mat(0.1, 0.2, -0.3, 0.4);
  P.acceleration[0] = Vec2(-9.81, 0.5);
  P.stress[0] << -1e4, 2e3, 0, 2e3, -3e4, 0, 0, 0, -1.5e4;
  P.external_force[0] = Vec2(3.0, -5.0);
  return P;
}

std::array<Vec2, 4> corners(const Particles<2>& P, std::size_t p) {
  std::array<Vec2, 4> c;
  const Vec2 signs[4] = {Vec2(-1, -1), Vec2(1, -1), Vec2(1, 1), Vec2(-1, 1)};
  for (std::size_t k = 0; k < 4; ++k)
    c[k] = P.x[p] + P.grid_F(p) * signs[k].cwiseProduct(P.half_size0[p]);
  return c;
}

// Reference coordinates of x in the voxel of point p of `P` (inside: every |r_d| <= h_d).
Vec2 voxel_coordinates(const Particles<2>& P, std::size_t p, const Vec2& x) {
  return P.grid_F(p).inverse() * (x - P.x[p]);
}

TEST(Splitting, CriterionNamesTheModeOfTheTalk) {
  const SplitSpec spec; // alpha 2, beta 1/2, gamma 1
  EXPECT_EQ(split_mode<2>(Mat2::Identity(), spec), SplitMode::None);
  EXPECT_EQ(split_mode<2>(mat(1.99, 0.99, 0.99, 0.51), spec), SplitMode::None);
  EXPECT_EQ(split_mode<2>(mat(2.01, 0, 0, 1), spec), SplitMode::Stretch);
  EXPECT_EQ(split_mode<2>(mat(1, 0, 0, 2.01), spec), SplitMode::Stretch);
  EXPECT_EQ(split_mode<2>(mat(0.49, 0, 0, 1), spec), SplitMode::Compression);
  EXPECT_EQ(split_mode<2>(mat(1, 0, 0, 0.49), spec), SplitMode::Compression);
  EXPECT_EQ(split_mode<2>(mat(1, 1.01, 0, 1), spec), SplitMode::Shear);
  EXPECT_EQ(split_mode<2>(mat(1, 0, -1.01, 1), spec), SplitMode::Shear);
}

// The talk's six pictures from a square voxel: stretch cuts the stretched axis, compression
// the other one, shear the axis whose edge was sheared (the longer deformed edge).
TEST(Splitting, EachModeCutsTheLongerDeformedEdge) {
  const Vec2 square(0.5, 0.5);
  EXPECT_EQ(split_axis<2>(mat(2, 0, 0, 1), square), 0);
  EXPECT_EQ(split_axis<2>(mat(1, 0, 0, 2), square), 1);
  EXPECT_EQ(split_axis<2>(mat(0.5, 0, 0, 1), square), 1);
  EXPECT_EQ(split_axis<2>(mat(1, 0, 0, 0.5), square), 0);
  EXPECT_EQ(split_axis<2>(mat(1, 1, 0, 1), square), 1);
  EXPECT_EQ(split_axis<2>(mat(1, 0, 1, 1), square), 0);
  // A voxel left twice as wide as tall by an earlier split is cut across its long side.
  EXPECT_EQ(split_axis<2>(Mat2::Identity(), Vec2(0.5, 0.25)), 0);
}

class SplitPoint : public ::testing::TestWithParam<int> {};

TEST_P(SplitPoint, ConservesMassVolumeMomentumAndKineticEnergyExactly) {
  const int axis = GetParam();
  Particles<2> P = one_point(mat(1.3, 0.4, -0.2, 0.9));
  // The velocity of a linear field v = v0 + L x at the parent; the children share it.
  P.v[0] = Vec2(0.2, -0.1) + mat(0.5, -1.5, 2.0, 0.25) * P.x[0];
  const Particles<2> before = P;
  const Index q = split_point(P, 0, axis);
  ASSERT_EQ(q, 1);
  ASSERT_EQ(P.size(), 2);
  EXPECT_EQ(P.mass[0] + P.mass[1], before.mass[0]);
  EXPECT_EQ(P.volume[0] + P.volume[1], before.volume[0]);
  EXPECT_EQ(P.volume0[0] + P.volume0[1], before.volume0[0]);
  const Vec2 momentum = P.mass[0] * P.v[0] + P.mass[1] * P.v[1];
  EXPECT_EQ(momentum, before.mass[0] * before.v[0]);
  const double kinetic =
      0.5 * P.mass[0] * P.v[0].squaredNorm() + 0.5 * P.mass[1] * P.v[1].squaredNorm();
  EXPECT_EQ(kinetic, 0.5 * before.mass[0] * before.v[0].squaredNorm());
  const Vec2 first_moment = P.mass[0] * P.x[0] + P.mass[1] * P.x[1];
  EXPECT_LE((first_moment - before.mass[0] * before.x[0]).norm(), kRoundOff);
  EXPECT_EQ(P.external_force[0] + P.external_force[1], before.external_force[0]);
  // volume = det F volume0 still holds for each child.
  for (std::size_t c = 0; c < 2; ++c)
    EXPECT_NEAR(P.volume[c], P.F[c].determinant() * P.volume0[c], kRoundOff * P.volume[c]);
}

TEST_P(SplitPoint, ChildrenTileTheParentsDeformedVoxel) {
  const int axis = GetParam();
  Particles<2> P = one_point(mat(1.3, 0.4, -0.2, 0.9));
  const Particles<2> parent = P;
  split_point(P, 0, axis);
  const Vec2 h = parent.half_size0[0];
  for (std::size_t c = 0; c < 2; ++c) {
    // Centroid: the centre of one half of the parent's voxel.
    const Vec2 r = voxel_coordinates(parent, 0, P.x[c]);
    EXPECT_NEAR(std::abs(r[axis]), 0.5 * h[axis], kRoundOff);
    EXPECT_NEAR(r[1 - axis], 0.0, kRoundOff);
    // Every corner of the child lies in the parent's deformed voxel.
    for (const Vec2& corner : corners(P, c)) {
      const Vec2 rc = voxel_coordinates(parent, 0, corner);
      EXPECT_LE(std::abs(rc.x()), h.x() * (1 + kRoundOff));
      EXPECT_LE(std::abs(rc.y()), h.y() * (1 + kRoundOff));
    }
    EXPECT_EQ(P.half_size0[c][axis], 0.5 * h[axis]);
    EXPECT_EQ(P.half_size0[c][1 - axis], h[1 - axis]);
    // The reference voxel follows, so patterns and voxels keep drawing the same material.
    Vec2 shift0 = Vec2::Zero();
    shift0[axis] = (c == 0 ? -0.5 : 0.5) * h[axis];
    EXPECT_LE((P.x0[c] - (parent.x0[0] + shift0)).norm(), kRoundOff);
  }
  // Together the two halves cover the parent: the outer corners are the parent's.
  const auto a = corners(P, 0), b = corners(P, 1), whole = corners(parent, 0);
  EXPECT_LE((a[0] - whole[0]).norm(), kRoundOff);
  EXPECT_LE((b[2] - whole[2]).norm(), kRoundOff);
}

TEST_P(SplitPoint, ChildrenShareTheStateAndRestartFSplit) {
  const int axis = GetParam();
  const Mat2 F = mat(1.3, 0.4, -0.2, 0.9);
  Particles<2> P = one_point(F);
  const Particles<2> parent = P;
  split_point(P, 0, axis);
  for (std::size_t c = 0; c < 2; ++c) {
    EXPECT_EQ(P.v[c], parent.v[0]);
    EXPECT_EQ(P.affine_velocity[c], parent.affine_velocity[0]);
    EXPECT_EQ(P.acceleration[c], parent.acceleration[0]);
    EXPECT_EQ(P.stress[c], parent.stress[0]);
    EXPECT_EQ(P.F[c], embedded<2>(F));
    EXPECT_LE((P.F[c] * P.split_origin_inverse[c] - Mat3::Identity()).norm(), kRoundOff);
    EXPECT_EQ(P.split_generation[c], 1);
  }
}

INSTANTIATE_TEST_SUITE_P(BothAxes, SplitPoint, ::testing::Values(0, 1));

// The history of a plastic point goes with both children: the same plastic strain, and the
// same stress on the next update.
TEST(Splitting, PlasticHistoryIsCopiedToTheChild) {
  MaterialSpec spec;
  spec.name = "soil";
  spec.model = MaterialModel::MohrCoulomb;
  spec.density = 1000;
  spec.youngs_modulus = 2e7;
  spec.poisson_ratio = 0.3;
  spec.cohesion = 1e3;
  spec.friction_angle = 30;
  const auto material = make_material(spec);
  std::vector<Mat3> F = {Mat3::Identity(), embedded<2>(mat(1.05, 0.02, 0.0, 0.96))};
  std::vector<Mat3> stress(2, Mat3::Zero());
  const std::vector<Index> ids = {0, 1};
  material->update_stress(ids, F, stress);
  std::vector<double> kappa(3, -1.0);
  material->plastic_strain(ids, kappa);
  ASSERT_GT(kappa[1], 0.0) << "the test point should have yielded";
  material->append_copies(2, std::vector<Index>{1});
  F.push_back(F[1]);
  stress.push_back(stress[1]);
  material->plastic_strain(std::vector<Index>{2}, kappa);
  EXPECT_EQ(kappa[2], kappa[1]);
  for (Mat3& f : F)
    f = embedded<2>(mat(1.01, 0.0, 0.0, 0.99)) * f;
  material->update_stress(std::vector<Index>{0, 1, 2}, F, stress);
  EXPECT_EQ(stress[2], stress[1]);
}

// A block of 4 x 2 points (h = 0.1, 2 per cell) and, optionally, a second block without a split
// block, with a traction on the first block's top.
const std::string kBlocks = R"(name: blocks
analysis: explicit
grid: {origin: [0, 0], extent: [2, 1], cell_size: 0.1}
materials:
  - {name: m, model: linear_elastic, density: 1000, youngs_modulus: 1.0e6, poisson_ratio: 0.3}
bodies:
  - {name: a, material: m, shape: rectangle, min: [0.4, 0.4], max: [0.6, 0.5],
     split: {alpha: 2, beta: 0.5, gamma: 1, max_generations: 2}}
  - {name: b, material: m, shape: rectangle, min: [1.4, 0.4], max: [1.6, 0.5]}
tractions:
  - {body: a, side: top, traction: [0, -100]}
time: {end_time: 0.01, cfl: 0.5}
)";

Scene<2> blocks(const std::vector<std::string>& overrides = {}) {
  return build_scene<2>(read_case_text(kBlocks, "blocks.yaml", overrides));
}

void deform_all(Scene<2>& scene, const Mat2& dF) {
  for (auto& F : scene.particles.F)
    F = embedded<2>(dF) * F;
}

Index count_body(const Scene<2>& scene, int body) {
  return static_cast<Index>(
      std::count(scene.particles.body.begin(), scene.particles.body.end(), body));
}

TEST(Splitting, StopsAtMaxGenerations) {
  Scene<2> scene = blocks();
  ASSERT_EQ(count_body(scene, 0), 8);
  const std::vector<Index> expected = {16, 32, 32, 32};
  for (const Index want : expected) {
    deform_all(scene, mat(2.5, 0, 0, 1));
    split_material_points(scene);
    EXPECT_EQ(count_body(scene, 0), want);
  }
  // The body without a split block never splits, however stretched.
  EXPECT_EQ(count_body(scene, 1), 8);
  // The batches cover every point once.
  EXPECT_EQ(static_cast<Index>(scene.particles_of_material[0].size()), scene.particles.size());
}

TEST(Splitting, MinSizeKeepsSmallChildrenFromForming) {
  // Half-width 0.025 stretched 2.5 times: a child 0.0625 across the cut.
  Scene<2> small = blocks({"bodies.a.split.min_size=0.07"});
  deform_all(small, mat(2.5, 0, 0, 1));
  EXPECT_EQ(split_material_points(small), 0);
  Scene<2> large = blocks({"bodies.a.split.min_size=0.06"});
  deform_all(large, mat(2.5, 0, 0, 1));
  EXPECT_EQ(split_material_points(large), 8);
}

TEST(Splitting, BodiesWithoutASplitBlockAllocateNothingAndNeverSplit) {
  Scene<2> scene = blocks({"bodies.a.split=~"});
  EXPECT_TRUE(scene.particles.split_origin_inverse.empty());
  EXPECT_TRUE(scene.particles.split_generation.empty());
  deform_all(scene, mat(3, 0, 0, 1));
  EXPECT_EQ(split_material_points(scene), 0);
  EXPECT_EQ(scene.particles.size(), 16);
}

double traction_sum_y(const Scene<2>& scene) {
  double sum = 0;
  for (const SurfaceLoad<2>& load : scene.surface_loads)
    sum += load.force.y();
  return sum;
}

// A vertical stretch cuts the top points across y: the loaded face goes to the upper child at
// its half-width. A horizontal stretch cuts them across x: each child takes half the force.
TEST(Splitting, TractionsFollowTheChildThatHoldsTheFace) {
  for (const int axis : {0, 1}) {
    Scene<2> scene = blocks();
    const double total = traction_sum_y(scene);
    const std::size_t loads = scene.surface_loads.size();
    deform_all(scene, axis == 0 ? mat(2.5, 0, 0, 1) : mat(1, 0, 0, 2.5));
    split_material_points(scene);
    EXPECT_EQ(traction_sum_y(scene), total);
    EXPECT_EQ(scene.surface_loads.size(), axis == 0 ? 2 * loads : loads);
    for (const SurfaceLoad<2>& load : scene.surface_loads) {
      const auto p = static_cast<std::size_t>(load.particle);
      EXPECT_EQ(load.offset.y(), scene.particles.half_size0[p].y());
      // The loaded face is the top of the body: the child's top edge is at y = 0.5 (F = I in
      // the reference).
      EXPECT_NEAR(scene.particles.x0[p].y() + load.offset.y(), 0.5, kRoundOff);
    }
  }
}

// Stepping a scene whose split block is never met gives bitwise the same state as the scene
// without one.
TEST(Splitting, NoSplitLeavesResultsUnchanged) {
  const std::vector<std::string> moving = {"bodies.a.velocity=[1, 0.5]",
                                           "bodies.b.velocity=[-1, 0]", "gravity=[0, -9.81]"};
  std::vector<std::string> never = moving;
  never.push_back("bodies.a.split={alpha: 1.0e9, beta: 1.0e-9, gamma: 1.0e9}");
  std::vector<std::string> without = moving;
  without.push_back("bodies.a.split=~");
  Scene<2> with_block = blocks(never), plain = blocks(without);
  auto s1 = make_explicit_solver(with_block);
  auto s2 = make_explicit_solver(plain);
  const double dt = s1->stable_dt(0.5);
  for (int step = 0; step < 200; ++step) {
    s1->step(dt);
    ASSERT_EQ(split_material_points(with_block), 0);
    s2->step(dt);
  }
  ASSERT_EQ(with_block.particles.size(), plain.particles.size());
  for (std::size_t p = 0; p < plain.particles.x.size(); ++p) {
    EXPECT_EQ(with_block.particles.x[p], plain.particles.x[p]);
    EXPECT_EQ(with_block.particles.v[p], plain.particles.v[p]);
    EXPECT_EQ(with_block.particles.stress[p], plain.particles.stress[p]);
  }
}

/// A fresh temporary directory per test, removed at the end.
class SplittingRuns : public talus::test_support::TemporaryDirectoryTest {
protected:
};

// A soft block thrown apart by a linear velocity field v_x = 4 (x - 0.5) stretches past
// alpha = 2 within the run; explicit and implicit-dynamic runs both split it and carry on,
// with the particle count in the time series and the totals in the summary.
const std::string kStretching = R"(name: stretching
analysis: explicit
grid: {origin: [0, 0], extent: [1, 0.5], cell_size: 0.05}
materials:
  - {name: m, model: neo_hookean, density: 1000, youngs_modulus: 10, poisson_ratio: 0.3}
bodies:
  - {name: a, material: m, shape: rectangle, min: [0.4, 0.2], max: [0.6, 0.3],
     velocity: ["0.8 * (x - 0.5) / 0.1", 0], split: {}}
time: {end_time: 0.25, cfl: 0.5}
output: {every_time: 0.05}
)";

TEST_F(SplittingRuns, ExplicitAndImplicitDynamicRunsSplitAndKeepTheirMass) {
  for (const std::string analysis : {"explicit", "implicit_dynamic"}) {
    std::vector<std::string> overrides = {"analysis=" + analysis,
                                          "output.fields=[velocity, mass, volume, F]"};
    if (analysis != "explicit")
      overrides.push_back("time.dt=0.005");
    const CaseSpec spec = read_case_text(kStretching, "stretching.yaml", overrides);
    RunOptions options;
    options.out_dir = root_ / analysis;
    options.progress = false;
    const RunResult r = run_case(spec, options);
    ASSERT_EQ(r.status, "completed") << analysis << ": " << r.message;
    EXPECT_GT(r.extra.at("splits"), 0.0) << analysis;
    EXPECT_EQ(r.extra.at("particles_initial"), 32.0);
    EXPECT_EQ(static_cast<double>(r.particles), 32.0 + r.extra.at("splits"));
    const CsvTable series = read_csv(options.out_dir / "timeseries.csv");
    const auto& count = series.column("particles");
    EXPECT_EQ(count.front(), 32.0);
    EXPECT_EQ(count.back(), static_cast<double>(r.particles));
    // Linear momentum along y stays zero and the symmetric field keeps x momentum at zero
    // (round-off of the sums of ~100 terms of order 1e-2 kg m/s).
    EXPECT_LE(std::abs(series.column("momentum_x").back()), 1e-12) << analysis;
    // Mass is conserved through the splits: the total of the last frame is the first frame's
    // (halving is exact in binary, so only the summation order rounds: 1e-14), and every
    // point, parent or child, keeps m = rho0 V0 (a split that halved the mass but not the
    // reference volume, or the reverse, breaks it).
    const ResultsReader results(options.out_dir / "run.h5");
    Index rows = 0, cols = 0;
    auto total_mass = [&](Index frame) {
      double sum = 0;
      for (double m : results.read(frame, "mass", &rows, &cols))
        sum += m;
      return sum;
    };
    const Index last = results.frame_count() - 1;
    EXPECT_NEAR(total_mass(last), total_mass(0), 1e-14 * total_mass(0)) << analysis;
    const auto mass = results.read(last, "mass", &rows, &cols);
    EXPECT_EQ(rows, r.particles) << analysis;
    const auto volume = results.read(last, "volume", &rows, &cols);
    const auto F = results.read(last, "F", &rows, &cols);
    for (Index p = 0; p < rows; ++p) {
      const auto s = static_cast<std::size_t>(p);
      const double* f = &F[s * static_cast<std::size_t>(cols)]; // row-major 3x3
      const double volume0 = volume[s] / (f[0] * f[4] - f[1] * f[3]);
      EXPECT_NEAR(mass[s], 1000.0 * volume0, 1e-12 * mass[s]) << analysis << ", point " << p;
    }
  }
}

} // namespace
} // namespace talus
