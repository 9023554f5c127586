// The water section (issue 40, step 1): what the reader takes and refuses, at its key, and what
// a scene with water starts from: saturated weights below the phreatic surface, a geostatic
// stress whose K0 acts on the effective stress, and water standing on a body refused.
#include "talus/core/errors.hpp"
#include "talus/io/case_reader.hpp"
#include "talus/io/results.hpp"
#include "talus/scene/scene.hpp"
#include "talus/scene/water_table.hpp"
#include "talus/solver/explicit_solver.hpp"

#include "cli_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace {

using namespace talus;
using talus::test_support::write_file;

// A 4 m x 3 m block of soil under gravity; line 1 is "name: ...". The water line is spliced in.
std::string block(const std::string& water, const std::string& material_extra = "",
                  const std::string& initial_stress = "") {
  return "name: wet\nanalysis: implicit_quasistatic\n"
         "grid: {origin: [0, 0], extent: [4, 4], cell_size: 0.5}\n"
         "gravity: [0, -10]\n" +
         water +
         "materials:\n"
         "  - {name: soil, model: mohr_coulomb, density: 1800, youngs_modulus: 2.0e7, "
         "poisson_ratio: 0.3, cohesion: 5.0e3, friction_angle: 30" +
         material_extra +
         "}\n"
         "bodies:\n"
         "  - {name: block, material: soil, shape: rectangle, min: [0, 0], max: [4, 3], "
         "particles_per_cell: 2" +
         initial_stress +
         "}\n"
         "boundaries: {x_min: roller, x_max: roller, y_min: fixed}\n"
         "time: {end_time: 1, dt: 0.5}\n";
}

/// The InputError reading (and building) the case gives, or a failure.
InputError error_of(const std::string& text) {
  try {
    build_scene<2>(read_case_text(text, "case.yaml"));
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "expected an InputError for\n" << text;
  return InputError({}, "");
}

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST(WaterInput, ReadsALevelOrAPolylineAndSaturatedWeights) {
  const CaseSpec level = read_case_text(block("water: {level: 2}\n"), "case.yaml");
  ASSERT_TRUE(level.water);
  EXPECT_EQ(level.water->unit_weight, 9810.0);
  EXPECT_EQ(WaterTable(*level.water).level(-100.0), 2.0);
  EXPECT_FALSE(level.materials[0].saturated_density);
  const CaseSpec line =
      read_case_text(block("water: {unit_weight: 1.0e4, phreatic: [[0, 1], [2, 2], [4, 2.5]]}\n",
                           ", saturated_unit_weight: 2.1e4"),
                     "case.yaml");
  const WaterTable table(*line.water);
  EXPECT_DOUBLE_EQ(table.level(-1.0), 1.0); // level beyond the ends
  EXPECT_DOUBLE_EQ(table.level(1.0), 1.5);
  EXPECT_DOUBLE_EQ(table.level(3.0), 2.25);
  EXPECT_DOUBLE_EQ(table.level(9.0), 2.5);
  EXPECT_DOUBLE_EQ(table.pore_pressure<2>(Vec<2>(1.0, 0.5)), 1.0e4);
  EXPECT_DOUBLE_EQ(table.pore_pressure<2>(Vec<2>(1.0, 2.0)), 0.0); // no suction above
  EXPECT_DOUBLE_EQ(*line.materials[0].saturated_density, 2100.0);  // 2.1e4 N/m^3 / 10 m/s^2
  EXPECT_FALSE(read_case_text(block(""), "case.yaml").water);
}

TEST(WaterInput, BadWaterIsRefusedAtItsKey) {
  struct Bad {
    std::string text, key, message;
  };
  const std::vector<Bad> cases = {
      {block("water: {level: 2, phreatic: [[0, 1]]}\n"), "water.phreatic",
       "give the phreatic surface once"},
      {block("water: {unit_weight: 9810}\n"), "water", "give the phreatic surface once"},
      {block("water: {phreatic: [[0, 1], [0, 2]]}\n"), "water.phreatic[1][0]",
       "the phreatic surface's x must ascend"},
      {block("water: {phreatic: [[0, 1, 2]]}\n"), "water.phreatic[0]",
       "a point of the phreatic surface is [x, y]"},
      {block("water: {level: 2, unit_weight: -1}\n"), "water.unit_weight", "must be > 0"},
      {block("water: {levle: 2}\n"), "water.levle", "did you mean 'level'"},
      {block("", ", saturated_density: 2000"), "materials[0]",
       "has a saturated weight (saturated_density or saturated_unit_weight) but the case has no "
       "water section"},
      {block("water: {level: 2}\n", ", saturated_density: 2000, saturated_unit_weight: 2.0e4"),
       "materials[0].saturated_unit_weight", "give either saturated_density"},
  };
  for (const Bad& c : cases) {
    SCOPED_TRACE(c.text);
    const InputError e = error_of(c.text);
    EXPECT_EQ(e.where().key_path, c.key) << e.what();
    EXPECT_TRUE(has(e.what(), c.message)) << e.what();
  }
  // Gravity along -y, since the pressure is hydrostatic.
  std::string sideways = block("water: {level: 2}\n");
  sideways.replace(sideways.find("[0, -10]"), 8, "[-10, 0]");
  const InputError e = error_of(sideways);
  EXPECT_EQ(e.where().key_path, "water");
  EXPECT_TRUE(has(e.what(), "water needs gravity along -y")) << e.what();
}

// Water above the body's top would press on its surface, which is not applied yet: refused.
TEST(WaterInput, WaterStandingOnABodyIsRefused) {
  const InputError e = error_of(block("water: {phreatic: [[0, 2], [3, 2], [4, 4]]}\n"));
  EXPECT_EQ(e.where().key_path, "water");
  EXPECT_TRUE(has(e.what(), "stands 0.375 m above body 'block' at x = 3.625")) << e.what();
  // At the top (within half a point spacing of it) is fine.
  EXPECT_NO_THROW(build_scene<2>(read_case_text(block("water: {level: 3}\n"), "case.yaml")));
}

// Below the surface a point weighs the saturated density; a geostatic stress integrates the dry
// and saturated weights above the point, K0 acts on the effective stress, and the point carries
// the total stress sigma' - u I. Hand-computed for the point nearest (1, 0.5): 2.5 m of soil
// above it, 1 m of it dry (1800 kg/m^3), 1.5 m saturated (2100), the water table at y = 2.
TEST(WaterInput, SaturatedWeightAndGeostaticEffectiveStress) {
  const Scene<2> scene = build_scene<2>(
      read_case_text(block("water: {unit_weight: 1.0e4, level: 2}\n", ", saturated_density: 2100",
                           ", initial_stress: {type: geostatic}"),
                     "case.yaml"));
  const auto& P = scene.particles;
  for (std::size_t s = 0; s < P.x.size(); ++s) {
    const double expected = P.x[s][1] < 2.0 ? 2100.0 : 1800.0;
    ASSERT_DOUBLE_EQ(P.mass[s] / P.volume0[s], expected) << "point " << s;
    const double y = P.x[s][1];
    const double dry = std::min(1.0, 3.0 - y), wet = std::max(0.0, 2.0 - y);
    const double total = -10.0 * (1800.0 * dry + 2100.0 * wet);
    const double u = 1.0e4 * wet;
    const double k0 = 0.3 / 0.7; // nu / (1 - nu), on the effective stress
    EXPECT_NEAR(P.stress[s](1, 1), total, 1e-9 * std::abs(total)) << "point " << s;
    EXPECT_NEAR(P.stress[s](0, 0), k0 * (total + u) - u, 1e-9 * std::abs(total)) << "point " << s;
    EXPECT_NEAR(P.stress[s](2, 2), P.stress[s](0, 0), 1e-9 * std::abs(total)) << "point " << s;
  }
}

// The explicit solver gives each point the total stress sigma' - u I with u where the point is:
// a block at rest, F = I, so sigma' = 0 and the points carry -u I (plane strain: sigma_zz too).
TEST(WaterInput, TheExplicitStressIsTotal) {
  std::string text = block("water: {unit_weight: 1.0e4, level: 2}\n");
  text.replace(text.find("implicit_quasistatic"), 20, "explicit");
  text.replace(text.find("time: {end_time: 1, dt: 0.5}"), 28, "time: {end_time: 1, cfl: 0.5}");
  Scene<2> scene = build_scene<2>(read_case_text(text, "case.yaml"));
  const auto solver = make_explicit_solver<2>(scene, false);
  const auto& P = scene.particles;
  int below = 0;
  for (std::size_t s = 0; s < P.x.size(); ++s) {
    const double u = 1.0e4 * std::max(0.0, 2.0 - P.x[s][1]);
    below += u > 0;
    EXPECT_NEAR((P.stress[s] + u * Mat3::Identity()).norm(), 0.0, 1e-9 * (1 + u)) << "point " << s;
  }
  EXPECT_GT(below, 0);
}

class WaterRun : public talus::test_support::Cli {};

// Frames write the pore pressure the total stress holds: in a quasi-static run with ramped
// gravity, u of the step, ramped with the weight and taken where the point stood at the step's
// start (the frame before). Two load steps of half the weight each.
TEST_F(WaterRun, FramesWriteThePorePressureTheStressHolds) {
  write_file(work() / "case.yaml",
             block("water: {unit_weight: 1.0e4, level: 2}\n", ", saturated_density: 2100") +
                 "output: {every_steps: 1}\n");
  const auto r = talus({"run", "case.yaml", "--out", "out"});
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  const ResultsReader results(work() / "out" / "run.h5");
  ASSERT_EQ(results.frame_count(), 3);
  Index rows = 0, dims = 0, cols = 0;
  for (const Index frame : {1, 2}) {
    const auto start = results.read(frame - 1, "position", &rows, &dims);
    const auto u = results.read(frame, "pore_pressure", &rows, &cols);
    ASSERT_EQ(cols, 1);
    const double factor = 0.5 * static_cast<double>(frame);
    int wet = 0;
    for (Index p = 0; p < rows; ++p) {
      const auto s = static_cast<std::size_t>(p);
      const double y = start[static_cast<std::size_t>(dims) * s + 1];
      const double expected = factor * 1.0e4 * std::max(0.0, 2.0 - y);
      wet += expected > 0;
      EXPECT_NEAR(u[s], expected, 1e-9 * (1.0 + expected)) << "frame " << frame << " point " << p;
    }
    EXPECT_GT(wet, 0);
  }
  // Frame 0: no weight yet, no pore pressure.
  const auto u0 = results.read(0, "pore_pressure", &rows, &cols);
  EXPECT_EQ(*std::max_element(u0.begin(), u0.end()), 0.0);
}

} // namespace
