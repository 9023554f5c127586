// Three-dimensional cases: the reader takes 3-vectors and the 3D body shapes (box, sphere,
// cylinder, prism) and refuses what a 3D or a 2D case cannot hold; the scene fills each body
// with points whose volumes add up to the body's (within the lattice's staircase), constrains
// the six faces, and spreads a traction over a box face with the right resultant; an explicit
// 3D run writes results ParaView's XDMF readers open.
#include "talus/core/errors.hpp"
#include "talus/io/case_reader.hpp"
#include "talus/scene/scene.hpp"
#include "talus/solver/run.hpp"
#include "temporary_directory.hpp"

#include <cmath>
#include <cstdlib>
#include <gtest/gtest.h>
#include <numbers>
#include <numeric>

namespace talus {
namespace {

const std::string kCase3d = R"(name: solid
dimension: 3
grid: {origin: [0, 0, 0], extent: [2, 1, 1], cell_size: 0.1}
materials:
  - {name: m, model: neo_hookean, density: 1000, youngs_modulus: 1.0e6, poisson_ratio: 0.3}
bodies:
  - {name: block, material: m, shape: box, min: [0.1, 0.1, 0.1], max: [0.5, 0.3, 0.6],
     particles_per_cell: 2, velocity: [1, 0, -1]}
boundaries: {x_min: fixed, z_max: roller}
time: {end_time: 0.001, cfl: 0.5}
)";

/// kCase3d with one occurrence of `from` replaced by `to`.
std::string with(const std::string& from, const std::string& to, std::string text = kCase3d) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return at == std::string::npos ? text : text.replace(at, from.size(), to);
}

double total_volume(const Scene<3>& scene) {
  return std::accumulate(scene.particles.volume0.begin(), scene.particles.volume0.end(), 0.0);
}

void expect_refused(const std::string& text, const std::string& message) {
  try {
    read_case_text(text, "case.yaml");
    ADD_FAILURE() << "accepted; expected: " << message;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
  }
}

TEST(Scene3d, ReaderTakesThreeVectorsAndTheSixFaces) {
  const CaseSpec spec = read_case_text(kCase3d, "case.yaml");
  EXPECT_EQ(spec.dimension, 3);
  EXPECT_EQ(spec.grid.extent, Vec3(2, 1, 1));
  EXPECT_EQ(spec.bodies[0].max, Vec3(0.5, 0.3, 0.6));
  EXPECT_EQ(spec.bodies[0].velocity, Vec3(1, 0, -1));
  EXPECT_EQ(spec.boundaries[kXMin], FaceCondition::Fixed);
  EXPECT_EQ(spec.boundaries[kZMax], FaceCondition::Roller);
  EXPECT_EQ(spec.boundaries[kZMin], FaceCondition::Free);
}

TEST(Scene3d, ReaderRefusesWhatTheDimensionCannotHold) {
  expect_refused(with("velocity: [1, 0, -1]", "velocity: [1, 0]"),
                 "case.yaml:8:39: key 'bodies[0].velocity': expected a 3-element list [x, y, z] "
                 "of numbers or expressions of the position, got a list of 2 elements");
  expect_refused(with("shape: box, min: [0.1, 0.1, 0.1], max: [0.5, 0.3, 0.6]",
                      "shape: polygon, vertices: [[0.1, 0.1], [0.5, 0.1], [0.3, 0.4]]"),
                 "key 'bodies[0].shape': unknown value 'polygon' (allowed: box, sphere, cylinder, "
                 "prism)");
  expect_refused(with("shape: box, min: [0.1, 0.1, 0.1], max: [0.5, 0.3, 0.6]",
                      "shape: sphere, centre: [0.5, 0.5, 0.5], radius: 0.6"),
                 "body 'block' extends outside the grid: the sphere covers");
  expect_refused(with("shape: box, min: [0.1, 0.1, 0.1], max: [0.5, 0.3, 0.6]",
                      "shape: prism, vertices: [[0.1, 0.1], [0.5, 0.1], [0.3, 0.4]], z_min: 0.5, "
                      "z_max: 0.2"),
                 "key 'bodies[0].z_max': z_max must be greater than z_min");
  // A 2D case has no z faces, and its points have two components.
  const std::string plane_box =
      with("origin: [0, 0, 0], extent: [2, 1, 1]", "origin: [0, 0], extent: [2, 1]",
           with("dimension: 3", "dimension: 2"));
  expect_refused(plane_box, "key 'bodies[0].shape': unknown value 'box' (allowed: rectangle, "
                            "disc, polygon)");
  const std::string plane = with("shape: box", "shape: rectangle", plane_box);
  expect_refused(plane, "key 'bodies[0].min': expected a 2-element list [x, y] (dimension: 2), "
                        "got a list of 3 elements");
  expect_refused(
      with("boundaries: {x_min: fixed, z_max: roller}", "boundaries: {z_max: fixed}",
           with("min: [0.1, 0.1, 0.1], max: [0.5, 0.3, 0.6]", "min: [0.1, 0.1], max: [0.5, 0.3]",
                with("velocity: [1, 0, -1]", "velocity: [1, 0]", plane))),
      "key 'boundaries.z_max': a 2D case has no face z_max");
  expect_refused(with("dimension: 3", "dimension: 4"), "key 'dimension': must be 2 (plane strain) "
                                                       "or 3");
}

// Each shape's points fill its volume: exactly for a box aligned with the lattice, within the
// staircase of the lattice otherwise (points whose centre lies inside count; the error is a
// fraction of a point layer over the surface). Measured at spacing 0.05: sphere +0.8 %,
// cylinder along a diagonal -2.2 %, prism with a slanted face 0 %; tolerances 2.5 %, 5 %, 1 %.
TEST(Scene3d, BodiesFillTheirVolume) {
  const Scene<3> box = build_scene<3>(read_case_text(kCase3d, "case.yaml"));
  EXPECT_EQ(box.particles.size(), 4 * 2 * 5 * 8);
  EXPECT_NEAR(total_volume(box), 0.4 * 0.2 * 0.5, 1e-15);

  struct Shape {
    std::string yaml;
    double volume;
    double tolerance; // relative
  };
  const double pi = std::numbers::pi;
  const Shape shapes[] = {
      {"shape: sphere, centre: [0.5, 0.5, 0.5], radius: 0.3", 4.0 / 3.0 * pi * 0.027, 0.025},
      {"shape: cylinder, axis: [[0.3, 0.3, 0.3], [1.5, 0.7, 0.7]], radius: 0.2",
       pi * 0.04 * std::sqrt(1.44 + 0.16 + 0.16), 0.05},
      {"shape: prism, vertices: [[0.2, 0.1], [1.8, 0.1], [0.2, 0.9]], z_min: 0.2, z_max: 0.8",
       0.5 * 1.6 * 0.8 * 0.6, 0.01},
  };
  for (const Shape& s : shapes) {
    SCOPED_TRACE(s.yaml);
    const Scene<3> scene = build_scene<3>(read_case_text(
        with("shape: box, min: [0.1, 0.1, 0.1], max: [0.5, 0.3, 0.6]", s.yaml), "case.yaml"));
    EXPECT_NEAR(total_volume(scene) / s.volume, 1.0, s.tolerance);
    for (std::size_t p = 0; p < scene.particles.x.size(); ++p)
      EXPECT_NEAR(scene.particles.mass[p], 1000.0 * std::pow(0.05, 3), 1e-15);
  }
}

TEST(Scene3d, FacesConstrainTheirNormalOrEveryComponent) {
  const Scene<3> scene = build_scene<3>(read_case_text(kCase3d, "case.yaml"));
  const auto mask = [&](Index i, Index j, Index k) {
    return scene.face_conditions.held({i, j, k});
  };
  EXPECT_EQ(mask(0, 3, 4), 0b111);  // x_min fixed: all three components
  EXPECT_EQ(mask(5, 3, 10), 0b100); // z_max roller: the normal, z
  EXPECT_EQ(mask(5, 3, 4), 0);      // inside
  EXPECT_EQ(mask(0, 3, 10), 0b111); // the edge of both
  EXPECT_EQ(mask(20, 3, 0), 0);     // x_max and z_min are free
  // The reaction of the fixed face takes every component it holds.
  for (int d = 0; d < 3; ++d)
    EXPECT_EQ(scene.face_conditions.reaction_faces({0, 3, 4})[static_cast<std::size_t>(d)], kXMin);
}

// A traction on the box's front face (z_max) loads the points of its last layer with their
// share of the face: the resultant is the traction times the face's area.
TEST(Scene3d, TractionOnABoxFaceHasTheRightResultant) {
  const Scene<3> scene = build_scene<3>(read_case_text(
      kCase3d + "tractions:\n  - {body: block, side: front, traction: [0, 0, -2.0e3]}\n",
      "case.yaml"));
  Vec3 total = Vec3::Zero();
  for (const auto& load : scene.surface_loads) {
    total += load.force;
    EXPECT_DOUBLE_EQ(load.offset.z(), 0.025); // to the face: half a point spacing
  }
  EXPECT_EQ(scene.surface_loads.size(), 8u * 4u);
  EXPECT_NEAR(total.z(), -2.0e3 * 0.4 * 0.2, 1e-9);
  EXPECT_EQ(total.x(), 0.0);
}

class Run3d : public test_support::TemporaryDirectoryTest {};

// An explicit 3D run of the block: it completes, writes 3-column positions and velocities, and
// run.xmf opens in both of ParaView's XDMF readers with the voxels as hexahedra and the grid as
// a 3D lattice (tests/python/check_post.py).
TEST_F(Run3d, ExplicitRunWritesResultsParaViewOpens) {
  CaseSpec spec = read_case_text(
      kCase3d, "case.yaml", {"output={every_time: 0.0005, voxels: true, stress_recovery: true}"});
  RunOptions options;
  options.out_dir = root_ / "run";
  options.progress = false;
  const RunResult r = run_case(spec, options);
  ASSERT_EQ(r.status, "completed") << r.message;
  EXPECT_EQ(r.particles, 320);
  const std::string script = std::string(TALUS_TESTS_DIR) + "/python/check_post.py";
  EXPECT_EQ(std::system(
                ("/usr/bin/python3 '" + script + "' '" + options.out_dir.string() + "' > /dev/null")
                    .c_str()),
            0);
}

} // namespace
} // namespace talus
