// Case-file reader: one complete valid case with its defaults and locations, and the --set
// overrides (the errors: test_case_reader_errors.cpp).
#include "case_reader_fixtures.hpp"

#include "talus/io/case_reader.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>
#include <vector>

namespace talus {
namespace {

using namespace case_reader_test;

// --- valid input -----------------------------------------------------------------------------

TEST(CaseReader, ParsesCompleteCase) {
  const CaseSpec c = read_case_text(kCase, "cases/discs.yaml");
  EXPECT_EQ(c.name, "colliding_discs");
  EXPECT_EQ(c.source_file, "cases/discs.yaml");
  EXPECT_EQ(c.source_text, kCase);
  EXPECT_TRUE(c.overrides.empty());
  EXPECT_EQ(c.analysis, AnalysisType::Explicit);
  EXPECT_EQ(c.dimension, 2);

  expect_vec(c.grid.origin, -0.5, 0);
  expect_vec(c.grid.extent, 1.5, 1);
  EXPECT_DOUBLE_EQ(c.grid.cell_size, 0.025);

  ASSERT_EQ(c.materials.size(), 2u);
  EXPECT_EQ(c.materials[0].name, "disc");
  EXPECT_EQ(c.materials[0].model, MaterialModel::LinearElastic);
  EXPECT_DOUBLE_EQ(c.materials[0].density, 20);
  EXPECT_DOUBLE_EQ(c.materials[0].youngs_modulus, 1.0e5);
  EXPECT_DOUBLE_EQ(c.materials[0].poisson_ratio, 0.3);
  EXPECT_EQ(c.materials[1].name, "rubber");
  EXPECT_EQ(c.materials[1].model, MaterialModel::NeoHookean);
  EXPECT_DOUBLE_EQ(c.materials[1].density, 1100);
  EXPECT_DOUBLE_EQ(c.materials[1].youngs_modulus, 2e6);
  EXPECT_DOUBLE_EQ(c.materials[1].poisson_ratio, 0.45);

  ASSERT_EQ(c.bodies.size(), 3u);
  const BodySpec& lower = c.bodies[0];
  EXPECT_EQ(lower.name, "lower");
  EXPECT_EQ(lower.material, "disc");
  EXPECT_EQ(lower.material_index, 0);
  EXPECT_EQ(lower.shape, BodyShape::Disc);
  expect_vec(lower.centre, 0.2, 0.2);
  EXPECT_DOUBLE_EQ(lower.radius, 0.2);
  EXPECT_EQ(lower.particles_per_cell, 2);
  expect_vec(lower.velocity, 7, -7);
  EXPECT_DOUBLE_EQ(lower.angular_velocity, 0);
  const BodySpec& upper = c.bodies[1];
  EXPECT_EQ(upper.name, "upper");
  EXPECT_EQ(upper.material_index, 1);
  EXPECT_EQ(upper.shape, BodyShape::Rectangle);
  expect_vec(upper.min, 0.5, 0.5);
  expect_vec(upper.max, 0.8, 0.9);
  EXPECT_EQ(upper.particles_per_cell, 3);
  expect_vec(upper.velocity, 0, 0);
  EXPECT_DOUBLE_EQ(upper.angular_velocity, -1.5);
  const BodySpec& wedge = c.bodies[2];
  EXPECT_EQ(wedge.shape, BodyShape::Polygon);
  EXPECT_EQ(wedge.material_index, 0);
  ASSERT_EQ(wedge.vertices.size(), 3u);
  expect_vec(wedge.vertices[0], -0.4, 0.1);
  expect_vec(wedge.vertices[1], -0.1, 0.1);
  expect_vec(wedge.vertices[2], -0.25, 0.4);

  expect_vec(c.gravity, 0, -9.81);
  EXPECT_EQ(c.boundaries[kXMin], FaceCondition::Fixed);
  EXPECT_EQ(c.boundaries[kXMax], FaceCondition::Free);
  EXPECT_EQ(c.boundaries[kYMin], FaceCondition::Roller);
  EXPECT_EQ(c.boundaries[kYMax], FaceCondition::Free);

  ASSERT_EQ(c.point_loads.size(), 2u);
  EXPECT_EQ(c.point_loads[0].name, "tip");
  expect_vec(c.point_loads[0].point, 0.8, 0.9);
  expect_vec(c.point_loads[0].force, 0, -10);
  EXPECT_EQ(c.point_loads[1].name, "load1");
  expect_vec(c.point_loads[1].force, 1, 0);

  ASSERT_EQ(c.tractions.size(), 1u);
  EXPECT_EQ(c.tractions[0].body, "upper");
  EXPECT_EQ(c.tractions[0].body_index, 1);
  EXPECT_EQ(c.tractions[0].side, kYMax);
  expect_vec(c.tractions[0].traction, 0, -100);

  EXPECT_DOUBLE_EQ(c.time.end_time, 0.05);
  ASSERT_TRUE(c.time.cfl.has_value());
  EXPECT_DOUBLE_EQ(*c.time.cfl, 0.5);
  EXPECT_FALSE(c.time.dt.has_value());
  EXPECT_EQ(c.time.max_steps, 100000);

  ASSERT_TRUE(c.output.every_steps.has_value());
  EXPECT_EQ(*c.output.every_steps, 10);
  EXPECT_FALSE(c.output.every_time.has_value());
  EXPECT_EQ(c.output.fields,
            (std::vector<OutputField>{OutputField::Velocity, OutputField::DeformationGradient,
                                      OutputField::Stress}));

  ASSERT_EQ(c.probes.size(), 2u);
  EXPECT_EQ(c.probes[0].name, "tip");
  ASSERT_TRUE(c.probes[0].point.has_value());
  expect_vec(*c.probes[0].point, 0.8, 0.9);
  EXPECT_FALSE(c.probes[0].particle.has_value());
  EXPECT_EQ(c.probes[1].name, "first");
  ASSERT_TRUE(c.probes[1].particle.has_value());
  EXPECT_EQ(*c.probes[1].particle, 0);
  EXPECT_FALSE(c.probes[1].point.has_value());

  EXPECT_EQ(c.solver.shape, ShapeFunction::Linear);
  EXPECT_EQ(c.solver.scheme, UpdateScheme::USF);
  EXPECT_DOUBLE_EQ(c.solver.flip, 0.95);
}

TEST(CaseReader, RecordsWhereEachItemIs) {
  const CaseSpec c = read_case_text(kCase, "case.yaml");
  EXPECT_EQ(c.grid.where.file, "case.yaml");
  EXPECT_EQ(c.grid.where.line, 5);
  EXPECT_EQ(c.grid.where.column, 3);
  EXPECT_EQ(c.grid.where.key_path, "grid");
  EXPECT_EQ(c.materials[1].where.line, 14);
  EXPECT_EQ(c.materials[1].where.column, 5);
  EXPECT_EQ(c.materials[1].where.key_path, "materials[1]");
  EXPECT_EQ(c.bodies[2].where.line, 33);
  EXPECT_EQ(c.bodies[2].where.key_path, "bodies[2]");
  EXPECT_EQ(c.point_loads[1].where.line, 43);
  EXPECT_EQ(c.point_loads[1].where.column, 5);
  EXPECT_EQ(c.tractions[0].where.key_path, "tractions[0]");
  EXPECT_EQ(c.probes[1].where.line, 55);
}

TEST(CaseReader, AppliesDefaults) {
  const CaseSpec c = read_case_text(kMinimal, "min.yaml");
  EXPECT_EQ(c.analysis, AnalysisType::Explicit);
  EXPECT_EQ(c.dimension, 2);
  expect_vec(c.grid.origin, 0, 0);
  ASSERT_EQ(c.bodies.size(), 1u);
  EXPECT_EQ(c.bodies[0].particles_per_cell, 2);
  expect_vec(c.bodies[0].velocity, 0, 0);
  EXPECT_DOUBLE_EQ(c.bodies[0].angular_velocity, 0);
  expect_vec(c.gravity, 0, 0);
  EXPECT_EQ(c.boundaries[kXMin], FaceCondition::Free);
  EXPECT_EQ(c.boundaries[kYMax], FaceCondition::Free);
  EXPECT_TRUE(c.point_loads.empty());
  EXPECT_TRUE(c.tractions.empty());
  EXPECT_TRUE(c.probes.empty());
  ASSERT_TRUE(c.time.dt.has_value());
  EXPECT_DOUBLE_EQ(*c.time.dt, 5e-5);
  EXPECT_FALSE(c.time.cfl.has_value());
  EXPECT_EQ(c.time.max_steps, 10000000);
  EXPECT_FALSE(c.output.every_steps.has_value());
  EXPECT_FALSE(c.output.every_time.has_value());
  EXPECT_EQ(c.output.fields.size(), 6u);
  EXPECT_EQ(c.solver.shape, ShapeFunction::Gimp);
  EXPECT_EQ(c.solver.scheme, UpdateScheme::MUSL);
  EXPECT_DOUBLE_EQ(c.solver.flip, 1.0);
}

TEST(CaseReader, EmptyOptionalSectionIsTheDefault) {
  const CaseSpec c = read_case_text(kMinimal + "output:\nsolver:\nprobes:\n", "min.yaml");
  EXPECT_FALSE(c.output.every_steps.has_value());
  EXPECT_EQ(c.solver.scheme, UpdateScheme::MUSL);
}

TEST(CaseReader, AcceptsWholeNumberWrittenAsFloatForIntegers) {
  const CaseSpec c =
      read_case_text(with(kCase, "max_steps: 100000", "max_steps: 1e6"), "case.yaml");
  EXPECT_EQ(c.time.max_steps, 1000000);
}

TEST(CaseReader, ReadsFileFromDisk) {
  const auto path = std::filesystem::temp_directory_path() /
                    ("talus_case_reader_test_" + std::to_string(::getpid()) + ".yaml");
  {
    std::ofstream out(path);
    out << kMinimal;
  }
  const CaseSpec c = read_case_file(path.string(), {"solver.flip=0.5"});
  std::filesystem::remove(path);
  EXPECT_EQ(c.name, "minimal");
  EXPECT_EQ(c.source_file, path.string());
  EXPECT_EQ(c.source_text, kMinimal);
  EXPECT_EQ(c.overrides, std::vector<std::string>{"solver.flip=0.5"});
  EXPECT_DOUBLE_EQ(c.solver.flip, 0.5);
}

// --- --set overrides -------------------------------------------------------------------------

TEST(CaseReaderOverrides, ByIndexAndByName) {
  const CaseSpec c =
      read_case_text(kCase, "case.yaml",
                     {"materials[0].youngs_modulus=2e5", "materials.1.density=1000",
                      "materials.rubber.poisson_ratio=0.4", "bodies.upper.velocity=[1, 2]",
                      "solver.shape=gimp", "bodies[2].vertices[2]=[-0.25, 0.5]"});
  EXPECT_DOUBLE_EQ(c.materials[0].youngs_modulus, 2e5);
  EXPECT_DOUBLE_EQ(c.materials[1].density, 1000);
  EXPECT_DOUBLE_EQ(c.materials[1].poisson_ratio, 0.4);
  expect_vec(c.bodies[1].velocity, 1, 2);
  EXPECT_EQ(c.solver.shape, ShapeFunction::Gimp);
  expect_vec(c.bodies[2].vertices[2], -0.25, 0.5);
  ASSERT_EQ(c.overrides.size(), 6u);
  EXPECT_EQ(c.overrides[3], "bodies.upper.velocity=[1, 2]");
  // The text stays the file's text; overrides are recorded separately.
  EXPECT_EQ(c.source_text, kCase);
}

TEST(CaseReaderOverrides, LaterOverrideWins) {
  const CaseSpec c = read_case_text(kCase, "case.yaml", {"solver.flip=0.2", "solver.flip=0.7"});
  EXPECT_DOUBLE_EQ(c.solver.flip, 0.7);
}

TEST(CaseReaderOverrides, CreatesMissingKeysAndSections) {
  const CaseSpec c = read_case_text(
      kMinimal, "min.yaml", {"solver.scheme=usl", "gravity=[0, -9.81]", "output.every_time=0.1"});
  EXPECT_EQ(c.solver.scheme, UpdateScheme::USL);
  expect_vec(c.gravity, 0, -9.81);
  ASSERT_TRUE(c.output.every_time.has_value());
  EXPECT_DOUBLE_EQ(*c.output.every_time, 0.1);
}

TEST(CaseReaderOverrides, DtAndCflReplaceEachOther) {
  const CaseSpec a = read_case_text(kCase, "case.yaml", {"time.dt=1e-4"});
  ASSERT_TRUE(a.time.dt.has_value());
  EXPECT_DOUBLE_EQ(*a.time.dt, 1e-4);
  EXPECT_FALSE(a.time.cfl.has_value());

  const CaseSpec b = read_case_text(kMinimal, "min.yaml", {"time.cfl=0.3"});
  ASSERT_TRUE(b.time.cfl.has_value());
  EXPECT_DOUBLE_EQ(*b.time.cfl, 0.3);
  EXPECT_FALSE(b.time.dt.has_value());

  const CaseSpec c = read_case_text(kCase, "case.yaml", {"output.every_time=0.01"});
  EXPECT_FALSE(c.output.every_steps.has_value());
  ASSERT_TRUE(c.output.every_time.has_value());
  EXPECT_DOUBLE_EQ(*c.output.every_time, 0.01);
}

TEST(CaseReaderOverrides, BadValueIsReportedAgainstTheOverride) {
  try {
    read_case_text(kCase, "case.yaml", {"materials.disc.youngs_modulus=-1"});
    ADD_FAILURE() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().file, "--set");
    EXPECT_EQ(e.where().line, 0);
    EXPECT_EQ(e.where().column, 0);
    EXPECT_EQ(e.where().key_path, "materials[0].youngs_modulus");
    EXPECT_STREQ(e.what(), "--set: key 'materials[0].youngs_modulus': must be > 0 (got -1) "
                           "(from --set materials.disc.youngs_modulus=-1)");
  }
  // Same checks as the file: wrong type, inside a replaced list item, NaN.
  expect_error(
      kCase,
      {"--set", 0, 0, "grid.extent",
       "expected a 2-element list [x, y] (dimension: 2), got a list of 3 elements (from --set "
       "grid.extent=[1, 1, 1])"},
      {"grid.extent=[1, 1, 1]"});
  expect_error(kCase,
               {"--set", 0, 0, "materials[1].density",
                "must be > 0 (got -5) (from --set materials.rubber={name: rubber, model: "
                "neo_hookean, density: -5, youngs_modulus: 1, poisson_ratio: 0.3})"},
               {"materials.rubber={name: rubber, model: neo_hookean, density: -5, "
                "youngs_modulus: 1, poisson_ratio: 0.3}"});
  expect_error(kCase, {"--set", 0, 0, "solver.flip", "must be a finite number (got .nan)"},
               {"solver.flip=.nan"});
  // A later file problem that the override did not touch keeps its file location.
  expect_error(with(kCase, "density: 20", "density: -2"),
               {"case.yaml", 11, 14, "materials[0].density", "must be > 0 (got -2)"},
               {"materials.disc.youngs_modulus=2e5"});
}

TEST(CaseReaderOverrides, CreatedKeyIsCheckedForUnknownKeys) {
  expect_error(
      kCase,
      {"--set", 0, 0, "time.dtt",
       "unknown key 'dtt' (allowed keys here: end_time, cfl, dt, max_steps, min_dt); did you "
       "mean 'dt'? (from --set time.dtt=1e-4)"},
      {"time.dtt=1e-4"});
}

TEST(CaseReaderOverrides, SectionCreatedByOverrideIsBlamedOnIt) {
  const std::string no_time = with(kMinimal, "time:\n  end_time: 1\n  dt: 5e-5\n", "");
  expect_error(no_time,
               {"--set", 0, 0, "time", "missing required key 'end_time' (from --set time.cfl=0.5)"},
               {"time.cfl=0.5"});
}

TEST(CaseReaderOverrides, MalformedOverrides) {
  expect_error(kCase,
               {"--set", 0, 0, "",
                "an override must have the form key.path=value (no '=' found) (in --set "
                "solver.flip)"},
               {"solver.flip"});
  expect_error(kCase,
               {"--set", 0, 0, "materials",
                "list index 5 is out of range: 'materials' has 2 item(s) (in --set "
                "materials[5].density=1)"},
               {"materials[5].density=1"});
  expect_error(
      kCase,
      {"--set", 0, 0, "name", "cannot go into 'name': it holds the single value 'colliding_discs'"},
      {"name.first=x"});
  expect_error(kCase,
               {"--set", 0, 0, "materials",
                "no item named 'steel' in list 'materials' (names: disc, rubber)"},
               {"materials.steel.density=1"});
  expect_error(kCase, {"--set", 0, 0, "", "malformed key path 'time..dt'"}, {"time..dt=1"});
  expect_error(kCase, {"--set", 0, 0, "", "empty key path before '='"}, {"=1"});
  expect_error(kCase, {"--set", 0, 0, "solver.flip", "the value '[1' is not valid YAML"},
               {"solver.flip=[1"});
  expect_error(kCase, {"--set", 0, 0, "grid", "'grid' is a map, not a list"}, {"grid[0]=1"});
}

// Initial velocity components may be expressions of the initial position (muparser).
TEST(CaseReader, VelocityExpressions) {
  const CaseSpec spec = read_case_text(
      with(kCase, "velocity: [7, -7]", "velocity: [\"2 * x\", 0.5*sin(pi*y)]"), "case.yaml");
  EXPECT_EQ(spec.bodies[0].velocity_expression[0], "2 * x");
  EXPECT_EQ(spec.bodies[0].velocity_expression[1], "0.5*sin(pi*y)");
  // Plain numbers stay numbers, without an expression.
  const CaseSpec plain = read_case_text(kCase, "case.yaml");
  EXPECT_TRUE(plain.bodies[0].velocity_expression[0].empty());
  expect_vec(plain.bodies[0].velocity, 7, -7);
}

// bodies[].split: defaults, every key, and each bad value at its key (file or --set).
TEST(CaseReader, SplitBlock) {
  const CaseSpec none = read_case_text(kCase, "case.yaml");
  EXPECT_FALSE(none.bodies[0].split.has_value());
  const CaseSpec defaults = read_case_text(kCase, "case.yaml", {"bodies.lower.split={}"});
  ASSERT_TRUE(defaults.bodies[0].split.has_value());
  EXPECT_EQ(defaults.bodies[0].split->alpha, 2.0);
  EXPECT_EQ(defaults.bodies[0].split->beta, 0.5);
  EXPECT_EQ(defaults.bodies[0].split->gamma, 1.0);
  EXPECT_EQ(defaults.bodies[0].split->max_generations, 3);
  EXPECT_EQ(defaults.bodies[0].split->min_size, 0.0);
  EXPECT_FALSE(defaults.bodies[1].split.has_value());
  const CaseSpec c =
      read_case_text(kCase, "case.yaml",
                     {"bodies.upper.split={alpha: 3, beta: 0.25, gamma: 0.5, max_generations: 30, "
                      "min_size: 0.01}"});
  ASSERT_TRUE(c.bodies[1].split.has_value());
  EXPECT_EQ(c.bodies[1].split->alpha, 3.0);
  EXPECT_EQ(c.bodies[1].split->beta, 0.25);
  EXPECT_EQ(c.bodies[1].split->gamma, 0.5);
  EXPECT_EQ(c.bodies[1].split->max_generations, 30);
  EXPECT_EQ(c.bodies[1].split->min_size, 0.01);
}

} // namespace
} // namespace talus
