// Axisymmetric scenes (geometry: axisymmetric): the reader's refusals, the per-radian volumes,
// masses and tractions the scene builds (their sums against closed-form ring integrals), the
// axis holding the radial component, and splitting keeping each ring's mass and volume.
#include "talus/core/errors.hpp"
#include "talus/io/case_reader.hpp"
#include "talus/scene/scene.hpp"
#include "talus/scene/splitting.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace {

using namespace talus;

// A solid cylinder r < 0.5, 0 < z < 1 (h = 0.125, 2 points per cell), a pressure on its top, a
// ring 0.75 < r < 1 on its side; density 1000.
const std::string kCylinder = R"(name: axi
analysis: implicit_quasistatic
geometry: axisymmetric
grid: {origin: [0, 0], extent: [1.25, 1.25], cell_size: 0.125}
materials:
  - {name: m, model: linear_elastic, density: 1000, youngs_modulus: 1.0e6, poisson_ratio: 0.3}
bodies:
  - {name: core, material: m, shape: rectangle, min: [0, 0], max: [0.5, 1],
     split: {alpha: 1.5, beta: 0.5, gamma: 1}}
  - {name: ring, material: m, shape: rectangle, min: [0.75, 0], max: [1, 1]}
tractions:
  - {body: core, side: top, traction: [0, -100]}
  - {body: ring, side: left, traction: [50, 0]}
time: {end_time: 1, dt: 1}
)";

Scene<2> cylinder(const std::vector<std::string>& overrides = {}) {
  return build_scene<2>(read_case_text(kCylinder, "axi.yaml", overrides));
}

double body_sum(const Scene<2>& scene, int body, const Array<double>& values) {
  double sum = 0;
  for (Index p = 0; p < scene.particles.size(); ++p)
    if (scene.particles.body[static_cast<std::size_t>(p)] == body)
      sum += values[static_cast<std::size_t>(p)];
  return sum;
}

Vec2 traction_sum(const Scene<2>& scene, int body) {
  Vec2 sum = Vec2::Zero();
  for (const SurfaceLoad<2>& load : scene.surface_loads)
    if (scene.particles.body[static_cast<std::size_t>(load.particle)] == body)
      sum += load.force;
  return sum;
}

// Per radian: a ring a < r < b of height H holds (b^2 - a^2) / 2 H; a face a < r < b at
// pressure t carries t (b^2 - a^2) / 2; the face r = a of height H carries t a H. Pappus's rule
// for each voxel is exact, so the sums hold to round-off.
TEST(Axisymmetric, VolumesMassesAndTractionsArePerRadian) {
  const Scene<2> scene = cylinder();
  const auto& P = scene.particles;
  EXPECT_NEAR(body_sum(scene, 0, P.volume0), 0.5 * 0.25 * 1.0, 1e-15);
  EXPECT_NEAR(body_sum(scene, 1, P.volume0), 0.5 * (1.0 - 0.5625) * 1.0, 1e-15);
  EXPECT_NEAR(body_sum(scene, 0, P.mass), 1000 * 0.5 * 0.25, 1e-11);
  EXPECT_NEAR(traction_sum(scene, 0).y(), -100 * 0.5 * 0.25, 1e-12);
  EXPECT_NEAR(traction_sum(scene, 1).x(), 50 * 0.75 * 1.0, 1e-12);
  // The same scene in plane strain: areas, not rings.
  const Scene<2> plane = cylinder({"geometry=plane_strain"});
  EXPECT_NEAR(body_sum(plane, 0, plane.particles.volume0), 0.5, 1e-15);
}

TEST(Axisymmetric, TheAxisHoldsTheRadialComponentOnly) {
  const Scene<2> scene = cylinder();
  const auto& g = scene.grid;
  Index on_axis = 0;
  for (Index n = 0; n < g.node_count(); ++n) {
    const double r = g.node_position(g.node_ijk(n))[0];
    const std::uint8_t mask = scene.face_conditions.held(g.node_ijk(n));
    // The case has no face conditions: the axis alone holds r, and nothing holds z.
    EXPECT_EQ(mask, r <= 0.0 ? 1u : 0u) << "node " << n << " at r = " << r;
    on_axis += r == 0.0;
  }
  EXPECT_GT(on_axis, 0);
  // Plane strain leaves the same nodes free.
  const Scene<2> plane = cylinder({"geometry=plane_strain"});
  for (Index n = 0; n < g.node_count(); ++n)
    EXPECT_EQ(plane.face_conditions.held(g.node_ijk(n)), 0u);
}

// A split across r puts the children at r -+ s: each takes the ring of its half, so the
// children's masses and volumes are in the ratio of their radii and sum to the parent's;
// the top traction shared across the cut follows the same ratio.
TEST(Axisymmetric, SplittingKeepsEachRingsMassAndVolume) {
  Scene<2> scene = cylinder();
  auto& P = scene.particles;
  const double mass = body_sum(scene, 0, P.mass), volume = body_sum(scene, 0, P.volume);
  const Vec2 traction = traction_sum(scene, 0);
  const Index before = P.size();
  for (Index p = 0; p < P.size(); ++p)
    if (P.body[static_cast<std::size_t>(p)] == 0)
      P.F[static_cast<std::size_t>(p)](0, 0) = 1.6; // stretched along r beyond alpha
  const Index splits = split_material_points(scene);
  ASSERT_GT(splits, 0);
  EXPECT_EQ(P.size(), before + splits);
  EXPECT_NEAR(body_sum(scene, 0, P.mass), mass, 1e-12 * mass);
  EXPECT_NEAR(body_sum(scene, 0, P.volume), volume, 1e-12 * volume);
  EXPECT_NEAR(traction_sum(scene, 0).y(), traction.y(), 1e-12 * std::abs(traction.y()));
  // Density is unchanged everywhere: mass and volume were split in the same ratio.
  for (Index p = 0; p < P.size(); ++p) {
    const auto s = static_cast<std::size_t>(p);
    EXPECT_NEAR(P.mass[s] / P.volume0[s], 1000.0, 1e-9);
  }
  // The child nearer the axis is lighter: the first point (r = h/4) split into r = h/4 -+ ...
  const auto first = static_cast<std::size_t>(0), child = static_cast<std::size_t>(before);
  EXPECT_LT(P.x[first][0], P.x[child][0]);
  EXPECT_NEAR(P.mass[first] / P.mass[child], P.x[first][0] / P.x[child][0], 1e-12);
}

void expect_refused(const std::string& text, const std::string& key_path, int line,
                    const std::string& part) {
  try {
    read_case_text(text, "axi.yaml");
    ADD_FAILURE() << "expected an InputError containing '" << part << "'";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().key_path, key_path) << e.what();
    EXPECT_EQ(e.where().line, line) << e.what();
    EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
  }
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

TEST(Axisymmetric, ReaderRefusesBodiesAcrossTheAxisAndAxisymmetryIn3D) {
  // A grid reaching r < 0 (allowed: its nodes there carry nothing), so that the bodies below
  // fit in the grid and only the axis refuses them.
  const std::string wide = replaced(kCylinder, "origin: [0, 0], extent: [1.25, 1.25]",
                                    "origin: [-0.5, 0], extent: [1.75, 1.25]");
  EXPECT_NO_THROW(read_case_text(wide, "axi.yaml"));
  expect_refused(replaced(wide, "min: [0, 0], max: [0.5, 1]", "min: [-0.25, 0], max: [0.5, 1]"),
                 "bodies[0].min", 8, "reaches r = x < 0");
  expect_refused(replaced(wide, "shape: rectangle, min: [0.75, 0], max: [1, 1]",
                          "shape: disc, centre: [0.25, 0.5], radius: 0.375"),
                 "bodies[1].radius", 10, "reaches r = x < 0");
  expect_refused(replaced(wide, "shape: rectangle, min: [0.75, 0], max: [1, 1]",
                          "shape: polygon, vertices: [[0.7, 0], [1, 0], [-0.1, 1]]"),
                 "bodies[1].vertices[2]", 10, "reaches r = x < 0");
  expect_refused(replaced(kCylinder, "geometry: axisymmetric", "geometry: spherical"), "geometry",
                 3, "axisymmetric");
  expect_refused(
      replaced(kCylinder, "geometry: axisymmetric", "dimension: 3\ngeometry: axisymmetric"),
      "geometry", 4, "a 3D case is neither");
  expect_refused(
      replaced(kCylinder, "split: {alpha: 1.5, beta: 0.5, gamma: 1}", "angular_velocity: 1"),
      "bodies[0].angular_velocity", 9, "axisymmetric");
}

} // namespace
