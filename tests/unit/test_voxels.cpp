// Deformed voxels and colour patterns (Andersen 2013), the new `output` keys that switch them
// and the stress recovery on, and what real XDMF readers make of the written voxels and grid.
// Geometric truths: the corners are x_p + F (X_c - X_p), so F = I gives the initial lattice
// cell, the area is det F times the initial area and the centroid is x_p; a rotation keeps the
// edge lengths. Tolerances are round-off of a handful of operations on numbers of order 1.
#include "talus/core/errors.hpp"
#include "talus/io/case_reader.hpp"
#include "talus/io/results.hpp"
#include "talus/post/voxels.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

namespace talus {
namespace {

namespace fs = std::filesystem;
constexpr double kRoundOff = 1e-12;

Particles<2> one_point(const Vec2& x, const Vec2& half, const Mat2& F) {
  Particles<2> p;
  p.resize(1);
  p.x[0] = x;
  p.x0[0] = x;
  p.half_size0[0] = half;
  p.F[0] = embedded<2>(F);
  return p;
}

Voxels<2> voxels_of(const Particles<2>& p, const Vec2& pattern_origin, double pattern_size) {
  Voxels<2> v;
  update_voxels(p, pattern_origin, pattern_size, v);
  return v;
}

double shoelace_area(const std::array<Vec2, 4>& q) {
  double twice = 0;
  for (std::size_t c = 0; c < 4; ++c) {
    const Vec2& a = q[c];
    const Vec2& b = q[(c + 1) % 4];
    twice += a.x() * b.y() - b.x() * a.y();
  }
  return 0.5 * twice;
}

TEST(Voxels, IdentityGivesTheInitialLatticeCell) {
  const Particles<2> p = one_point(Vec2(1.0, 2.0), Vec2(0.25, 0.125), Mat2::Identity());
  const Voxels<2> v = voxels_of(p, Vec2::Zero(), 1.0);
  const std::array<Vec2, 4> want = {Vec2(0.75, 1.875), Vec2(1.25, 1.875), Vec2(1.25, 2.125),
                                    Vec2(0.75, 2.125)};
  for (std::size_t c = 0; c < 4; ++c)
    EXPECT_LE((v.corners[0][c] - want[c]).norm(), kRoundOff) << "corner " << c;
}

TEST(Voxels, AreaIsDetFTimesTheInitialAreaAndCentroidIsThePoint) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.8, 0.8);
  for (int trial = 0; trial < 20; ++trial) {
    Mat2 F = Mat2::Identity();
    F(0, 0) += u(rng);
    F(1, 1) += u(rng);
    F(0, 1) = u(rng);
    F(1, 0) = u(rng);
    if (F.determinant() <= 0.05)
      continue; // admissible deformation gradients only
    const Vec2 half(0.05, 0.03);
    const Particles<2> p = one_point(Vec2(u(rng), u(rng)), half, F);
    const Voxels<2> v = voxels_of(p, Vec2::Zero(), 1.0);
    EXPECT_NEAR(shoelace_area(v.corners[0]), F.determinant() * 4 * half.x() * half.y(), kRoundOff);
    const Vec2 centroid =
        0.25 * (v.corners[0][0] + v.corners[0][1] + v.corners[0][2] + v.corners[0][3]);
    EXPECT_LE((centroid - p.x[0]).norm(), kRoundOff);
  }
}

TEST(Voxels, RotationKeepsEdgeLengths) {
  const double angle = 0.7;
  Mat2 R;
  R << std::cos(angle), -std::sin(angle), std::sin(angle), std::cos(angle);
  const Particles<2> p = one_point(Vec2(0.3, 0.4), Vec2(0.1, 0.05), R);
  const Voxels<2> v = voxels_of(p, Vec2::Zero(), 1.0);
  const auto& q = v.corners[0];
  EXPECT_NEAR((q[1] - q[0]).norm(), 0.2, kRoundOff);
  EXPECT_NEAR((q[2] - q[1]).norm(), 0.1, kRoundOff);
  EXPECT_NEAR((q[1] - q[0]).dot(q[2] - q[1]), 0.0, kRoundOff); // still a rectangle
}

TEST(Voxels, PatternsFollowTheInitialLatticeNotTheCurrentPosition) {
  // Points at the centres of a lattice of spacing 0.25 from (-1, -1); pattern squares of side
  // 0.5, so 2 x 2 points per square. Moving the points must not change their colours.
  Particles<2> p;
  const double spacing = 0.25, side = 0.5;
  const Vec2 origin(-1.0, -1.0);
  for (int j = 0; j < 8; ++j)
    for (int i = 0; i < 8; ++i) {
      const Index k = p.size();
      p.resize(k + 1);
      const auto s = static_cast<std::size_t>(k);
      p.x0[s] = origin + spacing * Vec2(i + 0.5, j + 0.5);
      p.x[s] = p.x0[s] + Vec2(0.37, -0.11);
      p.half_size0[s] = Vec2::Constant(0.5 * spacing);
    }
  const Voxels<2> v = voxels_of(p, origin, side);
  for (int j = 0; j < 8; ++j)
    for (int i = 0; i < 8; ++i) {
      const auto s = static_cast<std::size_t>(8 * j + i);
      const int square_x = i / 2, square_y = j / 2;
      EXPECT_EQ(v.checker[s], (square_x + square_y) % 2) << i << ", " << j;
      EXPECT_EQ(v.stripes_horizontal[s], square_y % 2) << i << ", " << j;
      EXPECT_EQ(v.stripes_vertical[s], square_x % 2) << i << ", " << j;
    }
}

// --- the output keys ------------------------------------------------------------------------

const std::string kCase = R"(name: post
grid: {origin: [0, 0], extent: [1, 1], cell_size: 0.1}
materials:
  - {name: m, model: linear_elastic, density: 1000, youngs_modulus: 1.0e5, poisson_ratio: 0.3}
bodies:
  - {name: b, material: m, shape: rectangle, min: [0.2, 0.2], max: [0.6, 0.4]}
time: {end_time: 0.001, dt: 0.0005}
output:
  every_steps: 1
)";

std::string input_error(const std::string& output_lines) {
  try {
    read_case_text(kCase + output_lines, "case.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(OutputOptions, ReadsRecoveryVoxelsAndPatternSize) {
  const CaseSpec off = read_case_text(kCase, "case.yaml");
  EXPECT_FALSE(off.output.stress_recovery);
  EXPECT_FALSE(off.output.voxels);
  const CaseSpec on = read_case_text(
      kCase + "  stress_recovery: true\n  voxels: true\n  pattern_size: 0.2\n", "case.yaml");
  EXPECT_TRUE(on.output.stress_recovery);
  EXPECT_TRUE(on.output.voxels);
  EXPECT_EQ(on.output.pattern_size, 0.2);
}

TEST(OutputOptions, BadKeysAndValuesNameFileLineAndKey) {
  EXPECT_EQ(input_error("  voxels: yes\n"),
            "case.yaml:10:11: key 'output.voxels': expected true or false, got 'yes'");
  EXPECT_NE(input_error("  stress_recovry: true\n").find("did you mean 'stress_recovery'?"),
            std::string::npos);
  EXPECT_EQ(input_error("  voxels: true\n  pattern_size: -1\n"),
            "case.yaml:11:17: key 'output.pattern_size': must be > 0 (got -1)");
  EXPECT_NE(input_error("  pattern_size: 0.2\n").find("it needs 'voxels: true'"),
            std::string::npos);
}

// --- real readers ---------------------------------------------------------------------------

int run(const std::string& command) {
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(Voxels, XdmfReadersSeeVoxelCellsAndGridFields) {
  // A short run of the talk's colliding discs with voxels and stress recovery, then
  // tests/python/check_post.py opens run.xmf with VTK's XDMF readers (ParaView's).
  const fs::path dir = fs::temp_directory_path() / ("talus_voxels_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const fs::path case_file = fs::path(TALUS_TESTS_DIR).parent_path() / "cases/colliding_discs.yaml";
  ASSERT_EQ(run(std::string(TALUS_BINARY) + " run '" + case_file.string() + "' --out '" +
                dir.string() +
                "' --set time.end_time=0.005 --set output.voxels=true"
                " --set output.stress_recovery=true > /dev/null 2>&1"),
            0);
  const fs::path script = fs::path(TALUS_TESTS_DIR) / "python" / "check_post.py";
  EXPECT_EQ(run("/usr/bin/python3 '" + script.string() + "' '" + dir.string() + "'"), 0);

  // The C++ reader sees the same layout: the grid/ group covers the box of physical nodes the
  // points' stencils reach, 40 x 40 of the grid's 41 x 41 (no stencil reaches x = 0 or y = 0).
  const ResultsReader results(dir / "run.h5");
  const Index last = results.frame_count() - 1;
  Index n = 0, rows = 0, cols = 0;
  results.read(last, "position", &n, &cols);
  EXPECT_TRUE(results.frame_has(last, "voxels"));
  EXPECT_FALSE(results.frame_has(last, "voxels/nothing"));
  results.read(last, "voxels/corners", &rows, &cols);
  EXPECT_EQ(rows, 4 * n);
  EXPECT_EQ(cols, 2);
  results.read(last, "grid/stress", &rows, &cols);
  EXPECT_EQ(rows, 40 * 40);
  EXPECT_EQ(results.frame_attribute(last, "grid", "origin"), "0.025 0.025");
  EXPECT_EQ(results.frame_attribute(last, "grid", "nodes_x"), "40");
  EXPECT_EQ(cols, 6);
  results.read(last, "stress_smoothed", &rows, &cols);
  EXPECT_EQ(rows, n);
  fs::remove_all(dir);
}

} // namespace
} // namespace talus
