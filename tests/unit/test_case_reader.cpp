// Case-file reader: one complete valid case, every error class with its exact location, and the
// --set overrides.
#include "talus/io/case_reader.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>
#include <vector>

namespace talus {
namespace {

// Line numbers below refer to this text (line 1 is "name: colliding_discs").
const std::string kCase = R"(name: colliding_discs
analysis: explicit
dimension: 2
grid:
  origin: [-0.5, 0]
  extent: [1.5, 1]
  cell_size: 0.025
materials:
  - name: disc
    model: linear_elastic
    density: 20
    youngs_modulus: 1.0e5
    poisson_ratio: 0.3
  - name: rubber
    model: neo_hookean
    density: 1100
    youngs_modulus: 2e6
    poisson_ratio: 0.45
bodies:
  - name: lower
    material: disc
    shape: disc
    centre: [0.2, 0.2]
    radius: 0.2
    velocity: [7, -7]
  - name: upper
    material: rubber
    shape: rectangle
    min: [0.5, 0.5]
    max: [0.8, 0.9]
    particles_per_cell: 3
    angular_velocity: -1.5
  - name: wedge
    material: disc
    shape: polygon
    vertices: [[-0.4, 0.1], [-0.1, 0.1], [-0.25, 0.4]]
gravity: [0, -9.81]
boundaries:
  x_min: fixed
  y_min: roller
point_loads:
  - {name: tip, point: [0.8, 0.9], force: [0, -10]}
  - {point: [0.2, 0.2], force: [1, 0]}
tractions:
  - {body: upper, side: top, traction: [0, -100]}
time:
  end_time: 0.05
  cfl: 0.5
  max_steps: 100000
output:
  every_steps: 10
  fields: [velocity, F, stress]
probes:
  - {name: tip, point: [0.8, 0.9]}
  - {name: first, particle: 0}
solver:
  shape: linear
  scheme: usf
  flip: 0.95
)";

// The smallest valid case: everything optional left out. Its step is below the explicit
// stability limit h / c_p = 8.5e-5 s, which the reader enforces.
const std::string kMinimal = R"(name: minimal
grid:
  extent: [2, 1]
  cell_size: 0.5
materials:
  - {name: steel, model: linear_elastic, density: 7800, youngs_modulus: 2e11, poisson_ratio: 0.3}
bodies:
  - {name: block, material: steel, shape: rectangle, min: [0.5, 0], max: [1.5, 0.5]}
time:
  end_time: 1
  dt: 5e-5
)";

/// `text` with the first occurrence of `from` replaced by `to` (which must exist).
std::string with(const std::string& text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << "test bug: '" << from << "' not in the case text";
  if (at == std::string::npos)
    return text;
  std::string out = text;
  out.replace(at, from.size(), to);
  return out;
}

struct Expected {
  std::string file = "case.yaml";
  int line;
  int column;
  std::string key_path;
  std::string message_part;
};

/// Reads `text` expecting an InputError at exactly `e`.
void expect_error(const std::string& text, const Expected& e,
                  const std::vector<std::string>& overrides = {}) {
  try {
    read_case_text(text, "case.yaml", overrides);
    ADD_FAILURE() << "expected InputError containing '" << e.message_part << "'";
  } catch (const InputError& err) {
    EXPECT_EQ(err.where().file, e.file) << err.what();
    EXPECT_EQ(err.where().line, e.line) << err.what();
    EXPECT_EQ(err.where().column, e.column) << err.what();
    EXPECT_EQ(err.where().key_path, e.key_path) << err.what();
    EXPECT_NE(std::string(err.what()).find(e.message_part), std::string::npos)
        << "message: " << err.what() << "\nexpected to contain: " << e.message_part;
  }
}

void expect_vec(const Vec2& v, double x, double y) {
  EXPECT_DOUBLE_EQ(v.x(), x);
  EXPECT_DOUBLE_EQ(v.y(), y);
}
/// A 2D case's point: x, y and z = 0.
void expect_vec(const Vec3& v, double x, double y) {
  EXPECT_DOUBLE_EQ(v.x(), x);
  EXPECT_DOUBLE_EQ(v.y(), y);
  EXPECT_EQ(v.z(), 0.0);
}

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

// --- errors ----------------------------------------------------------------------------------

TEST(CaseReaderErrors, MissingFileNamesThePath) {
  const std::string path = "/nonexistent/dir/no_such_case.yaml";
  try {
    read_case_file(path);
    ADD_FAILURE() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().file, path);
    EXPECT_EQ(e.where().line, 0);
    EXPECT_NE(std::string(e.what()).find("cannot open case file '" + path + "'"), std::string::npos)
        << e.what();
  }
}

TEST(CaseReaderErrors, DirectoryIsNotACaseFile) {
  const std::string dir = std::filesystem::temp_directory_path().string();
  try {
    read_case_file(dir);
    ADD_FAILURE() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().file, dir);
    EXPECT_NE(std::string(e.what()).find("it is a directory"), std::string::npos) << e.what();
  }
}

TEST(CaseReaderErrors, YamlSyntaxErrorUsesParserLocation) {
  // Unclosed flow sequence: the parser notices at the start of the next key.
  expect_error("name: x\ngrid: [1, 2\ntime: 3\n",
               {"case.yaml", 3, 5, "", "YAML syntax error: end of sequence flow not found"});
  // Bad indentation.
  expect_error(with(kCase, "  cell_size: 0.025", "   cell_size: 0.025"),
               {"case.yaml", 7, 4, "", "YAML syntax error"});
}

TEST(CaseReaderErrors, EmptyOrNonMapDocument) {
  expect_error("", {"case.yaml", 0, 0, "", "the case file is empty"});
  expect_error("# only a comment\n", {"case.yaml", 0, 0, "", "the case file is empty"});
  expect_error("- a\n- b\n", {"case.yaml", 1, 1, "", "must be a map of keys"});
}

TEST(CaseReaderErrors, UnknownKeySuggestsClosest) {
  const std::string text = with(kCase, "youngs_modulus: 1.0e5", "youngs_modolus: 1.0e5");
  expect_error(text, {"case.yaml", 12, 5, "materials[0].youngs_modolus",
                      "unknown key 'youngs_modolus' (allowed keys here: name, model, density, "
                      "youngs_modulus, poisson_ratio, kinematics, yield_stress, "
                      "hardening_modulus, cohesion, friction_angle, dilation_angle, residual); "
                      "did you mean 'youngs_modulus'?"});
  // Exact full message (format comes from SourceLocation::to_string()).
  try {
    read_case_text(text, "case.yaml");
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "case.yaml:12:5: key 'materials[0].youngs_modolus': unknown key "
                           "'youngs_modolus' (allowed keys here: name, model, density, "
                           "youngs_modulus, poisson_ratio, kinematics, yield_stress, "
                           "hardening_modulus, cohesion, friction_angle, dilation_angle, "
                           "residual); did you mean 'youngs_modulus'?");
  }
}

TEST(CaseReaderErrors, UnknownKeyWithoutCloseMatchHasNoSuggestion) {
  const std::string text = kCase + "colour: red\n";
  expect_error(text, {"case.yaml", 60, 1, "colour",
                      "unknown key 'colour' (allowed keys here: "
                      "name, analysis, dimension, geometry, grid"});
  try {
    read_case_text(text, "case.yaml");
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).find("did you mean"), std::string::npos) << e.what();
  }
}

TEST(CaseReaderErrors, UnknownKeyInFlowMapAndNestedSection) {
  expect_error(
      with(kCase, "{name: tip, point: [0.8, 0.9], force", "{name: tip, pont: [0.8, 0.9], force"),
      {"case.yaml", 42, 17, "point_loads[0].pont", "did you mean 'point'?"});
  expect_error(with(kCase, "  max_steps: 100000", "  max_step: 100000"),
               {"case.yaml", 49, 3, "time.max_step", "did you mean 'max_steps'?"});
}

TEST(CaseReaderErrors, DuplicateKeyInMap) {
  expect_error(with(kCase, "    density: 20\n", "    density: 20\n    density: 30\n"),
               {"case.yaml", 12, 5, "materials[0].density",
                "key 'density' is given twice (first at line 11)"});
}

TEST(CaseReaderErrors, WrongTypeStringForNumber) {
  expect_error(with(kCase, "density: 20", "density: heavy"),
               {"case.yaml", 11, 14, "materials[0].density", "expected a number, got 'heavy'"});
  expect_error(with(kCase, "density: 20", "density: \"20\""),
               {"case.yaml", 11, 14, "materials[0].density",
                "expected a number, got the quoted string \"20\""});
  expect_error(with(kCase, "density: 20", "density:"), {"case.yaml", 11, 5, "materials[0].density",
                                                        "expected a number, got an empty value"});
}

TEST(CaseReaderErrors, WrongTypeScalarWhereListExpected) {
  expect_error(with(kCase, "fields: [velocity, F, stress]", "fields: velocity"),
               {"case.yaml", 52, 11, "output.fields", "expected a list, got 'velocity'"});
  expect_error(with(kMinimal,
                    "materials:\n  - {name: steel, model: linear_elastic, density: 7800, "
                    "youngs_modulus: 2e11, poisson_ratio: 0.3}\n",
                    "materials: steel\n"),
               {"case.yaml", 5, 12, "materials", "expected a list, got 'steel'"});
}

TEST(CaseReaderErrors, WrongTypeScalarWhereMapExpected) {
  expect_error(with(kCase, "boundaries:\n  x_min: fixed\n  y_min: roller\n", "boundaries: fixed\n"),
               {"case.yaml", 38, 13, "boundaries", "expected a map of keys (x_min, x_max"});
}

TEST(CaseReaderErrors, WrongTypeNonIntegerForInteger) {
  expect_error(
      with(kCase, "particles_per_cell: 3", "particles_per_cell: 2.5"),
      {"case.yaml", 31, 25, "bodies[1].particles_per_cell", "expected an integer, got '2.5'"});
  expect_error(with(kCase, "particle: 0}", "particle: first}"),
               {"case.yaml", 55, 29, "probes[1].particle", "expected an integer, got 'first'"});
}

TEST(CaseReaderErrors, WrongTypeVectorOfThreeElements) {
  expect_error(with(kCase, "extent: [1.5, 1]", "extent: [1.5, 1, 1]"),
               {"case.yaml", 6, 11, "grid.extent",
                "expected a 2-element list [x, y] (dimension: 2), got a list of 3 elements"});
  expect_error(with(kCase, "gravity: [0, -9.81]", "gravity: -9.81"),
               {"case.yaml", 37, 10, "gravity", "expected a 2-element list [x, y], got '-9.81'"});
  expect_error(with(kCase, "centre: [0.2, 0.2]", "centre: [0.2, x]"),
               {"case.yaml", 23, 19, "bodies[0].centre[1]", "expected a number, got 'x'"});
}

TEST(CaseReaderErrors, MissingRequiredKeyPointsAtEnclosingMap) {
  expect_error(with(kCase, "  extent: [1.5, 1]\n", ""),
               {"case.yaml", 5, 3, "grid", "missing required key 'extent'"});
  expect_error(with(kCase, "    density: 1100\n", ""),
               {"case.yaml", 14, 5, "materials[1]", "missing required key 'density'"});
  expect_error(with(kCase, "name: colliding_discs\n", ""),
               {"case.yaml", 1, 1, "", "missing required key 'name'"});
  expect_error(with(kCase, "    radius: 0.2\n", ""),
               {"case.yaml", 20, 5, "bodies[0]", "missing required key 'radius'"});
  expect_error(with(kCase, "  cfl: 0.5\n", ""),
               {"case.yaml", 47, 3, "time", "missing required key 'cfl' or 'dt'"});
}

TEST(CaseReaderErrors, EmptyRequiredLists) {
  expect_error(with(kMinimal,
                    "  - {name: block, material: steel, shape: rectangle, min: [0.5, 0], "
                    "max: [1.5, 0.5]}\n",
                    "  []\n"),
               {"case.yaml", 8, 3, "bodies", "list at least one body"});
}

struct NonPhysicalCase {
  std::string from, to;
  int line, column;
  std::string key_path, message;
};

TEST(CaseReaderErrors, NonPhysicalValues) {
  const std::vector<NonPhysicalCase> cases{
      {"youngs_modulus: 1.0e5", "youngs_modulus: 0", 12, 21, "materials[0].youngs_modulus",
       "must be > 0 (got 0)"},
      {"youngs_modulus: 1.0e5", "youngs_modulus: -3e5", 12, 21, "materials[0].youngs_modulus",
       "must be > 0 (got -3e5)"},
      {"poisson_ratio: 0.3", "poisson_ratio: 0.5", 13, 20, "materials[0].poisson_ratio",
       "must be in the open interval (-1, 0.5) (got 0.5)"},
      {"poisson_ratio: 0.3", "poisson_ratio: -1", 13, 20, "materials[0].poisson_ratio",
       "must be in the open interval (-1, 0.5) (got -1)"},
      {"density: 1100", "density: 0", 16, 14, "materials[1].density", "must be > 0 (got 0)"},
      {"density: 20", "density: -20", 11, 14, "materials[0].density", "must be > 0 (got -20)"},
      {"radius: 0.2", "radius: 0", 24, 13, "bodies[0].radius", "must be > 0 (got 0)"},
      {"radius: 0.2", "radius: -0.1", 24, 13, "bodies[0].radius", "must be > 0 (got -0.1)"},
      {"end_time: 0.05", "end_time: 0", 47, 13, "time.end_time", "must be > 0 (got 0)"},
      {"end_time: 0.05", "end_time: -1", 47, 13, "time.end_time", "must be > 0 (got -1)"},
      {"cfl: 0.5", "dt: 0", 48, 7, "time.dt", "must be > 0 (got 0)"},
      {"cfl: 0.5", "dt: -1e-4", 48, 7, "time.dt", "must be > 0 (got -1e-4)"},
      {"cfl: 0.5", "dt: 1e-3", 48, 7, "time.dt",
       "explicit time step 0.001 s is above the stability limit h / c_p"},
      {"cfl: 0.5", "cfl: 1", 48, 8, "time.cfl", "must be in the open interval (0, 1) (got 1)"},
      {"cfl: 0.5", "cfl: 1.5", 48, 8, "time.cfl", "must be in the open interval (0, 1) (got 1.5)"},
      {"cfl: 0.5", "cfl: 0", 48, 8, "time.cfl", "must be in the open interval (0, 1) (got 0)"},
      {"cfl: 0.5", "cfl: -0.5", 48, 8, "time.cfl",
       "must be in the open interval (0, 1) (got -0.5)"},
      {"cell_size: 0.025", "cell_size: 0.03", 7, 14, "grid.cell_size",
       "the grid extent in y (1 m) is not a whole number of cells of size 0.03 m"},
      {"extent: [1.5, 1]", "extent: [1.51, 1]", 7, 14, "grid.cell_size",
       "the grid extent in x (1.51 m) is not a whole number of cells"},
      {"cell_size: 0.025", "cell_size: 0", 7, 14, "grid.cell_size", "must be > 0 (got 0)"},
      {"extent: [1.5, 1]", "extent: [1.5, 0]", 6, 11, "grid.extent",
       "every component must be > 0 (got [1.5, 0])"},
      {"flip: 0.95", "flip: 1.5", 59, 9, "solver.flip", "must be in [0, 1] (got 1.5)"},
      {"particles_per_cell: 3", "particles_per_cell: 0", 31, 25, "bodies[1].particles_per_cell",
       "must be an integer from 1 to 16 (got 0)"},
      {"particles_per_cell: 3", "particles_per_cell: 17", 31, 25, "bodies[1].particles_per_cell",
       "must be an integer from 1 to 16 (got 17)"},
      {"max_steps: 100000", "max_steps: 0", 49, 14, "time.max_steps",
       "must be an integer >= 1 (got 0)"},
      {"every_steps: 10", "every_steps: 0", 51, 16, "output.every_steps",
       "must be an integer >= 1 (got 0)"},
      {"particle: 0}", "particle: -1}", 55, 29, "probes[1].particle",
       "must be an integer >= 0 (got -1)"},
      // NaN and infinity
      {"density: 20", "density: .nan", 11, 14, "materials[0].density",
       "must be a finite number (got .nan)"},
      {"youngs_modulus: 1.0e5", "youngs_modulus: .inf", 12, 21, "materials[0].youngs_modulus",
       "must be a finite number (got .inf)"},
      {"end_time: 0.05", "end_time: -.Inf", 47, 13, "time.end_time",
       "must be a finite number (got -.Inf)"},
      {"gravity: [0, -9.81]", "gravity: [.NaN, -9.81]", 37, 11, "gravity[0]",
       "must be a finite number (got .NaN)"},
      {"velocity: [7, -7]", "velocity: [7, 1e400]", 25, 19, "bodies[0].velocity[1]",
       "out of the double-precision range"},
      // Bodies outside the grid (the grid covers x in [-0.5, 1], y in [0, 1])
      {"radius: 0.2", "radius: 0.25", 24, 13, "bodies[0].radius",
       "body 'lower' extends outside the grid: the disc covers x in [-0.05, 0.45], y in [-0.05, "
       "0.45]; the grid covers x in [-0.5, 1], y in [0, 1]"},
      {"centre: [0.2, 0.2]", "centre: [0.2, 1.2]", 23, 13, "bodies[0].centre",
       "body 'lower' extends outside the grid: centre [0.2, 1.2] lies outside"},
      {"max: [0.8, 0.9]", "max: [1.1, 0.9]", 30, 10, "bodies[1].max",
       "body 'upper' extends outside the grid: max [1.1, 0.9] lies outside"},
      {"[[-0.4, 0.1], [-0.1, 0.1], [-0.25, 0.4]]", "[[-0.4, 0.1], [-0.1, 0.1], [-0.25, 1.4]]", 36,
       42, "bodies[2].vertices[2]",
       "body 'wedge' extends outside the grid: vertex [-0.25, 1.4] lies outside"},
      // Degenerate shapes
      {"max: [0.8, 0.9]", "max: [0.8, 0.5]", 30, 10, "bodies[1].max",
       "max must be greater than min in both x and y (min [0.5, 0.5], max [0.8, 0.5])"},
      {"[[-0.4, 0.1], [-0.1, 0.1], [-0.25, 0.4]]", "[[-0.4, 0.1], [-0.1, 0.1], [-0.25, 0.1]]", 36,
       15, "bodies[2].vertices", "the polygon has zero area"},
      {"[[-0.4, 0.1], [-0.1, 0.1], [-0.25, 0.4]]", "[[-0.4, 0.1], [-0.1, 0.1]]", 36, 15,
       "bodies[2].vertices", "a polygon needs at least 3 vertices (got 2)"},
      {"[[-0.4, 0.1], [-0.1, 0.1], [-0.25, 0.4]]",
       "[[-0.4, 0.1], [-0.1, 0.4], [-0.1, 0.1], [-0.4, 0.3]]", 36, 15, "bodies[2].vertices",
       "the polygon is not simple: edge 0-1 touches edge 2-3"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.to);
    expect_error(with(kCase, c.from, c.to), {"case.yaml", c.line, c.column, c.key_path, c.message});
  }
}

TEST(CaseReaderErrors, UnknownEnumValueListsAllowedValues) {
  expect_error(with(kCase, "model: linear_elastic", "model: plastic"),
               {"case.yaml", 10, 12, "materials[0].model",
                "unknown value 'plastic' (allowed: linear_elastic, neo_hookean, hencky, "
                "von_mises, tresca, mohr_coulomb, drucker_prager)"});
  expect_error(with(kCase, "scheme: usf", "scheme: msul"),
               {"case.yaml", 58, 11, "solver.scheme",
                "unknown value 'msul' (allowed: usl, usf, musl); did you mean 'musl'?"});
  expect_error(with(kCase, "x_min: fixed", "x_min: clamped"),
               {"case.yaml", 39, 10, "boundaries.x_min",
                "unknown value 'clamped' (allowed: free, fixed, roller)"});
  expect_error(with(kCase, "shape: rectangle", "shape: square"),
               {"case.yaml", 28, 12, "bodies[1].shape",
                "unknown value 'square' (allowed: rectangle, disc, polygon)"});
  expect_error(with(kCase, "side: top", "side: up"),
               {"case.yaml", 45, 25, "tractions[0].side",
                "unknown value 'up' (allowed: left, right, bottom, top)"});
  expect_error(
      with(kCase, "[velocity, F, stress]", "[velocity, f, stress]"),
      {"case.yaml", 52, 22, "output.fields[1]",
       "unknown value 'f' (allowed: velocity, mass, volume, F, stress, material, plastic_strain, "
       "reference_position)"});
}

TEST(CaseReaderErrors, UnsupportedAnalysisAndDimension) {
  expect_error(with(kCase, "analysis: explicit", "analysis: implicit_dynamic"),
               {"case.yaml", 48, 8, "time.cfl", "a CFL number applies to explicit analyses"});
  // The implicit analysis exists, but it steps loads by dt, not by a CFL number.
  expect_error(with(kCase, "analysis: explicit", "analysis: implicit_quasistatic"),
               {"case.yaml", 48, 8, "time.cfl", "a CFL number applies to explicit analyses"});
  expect_error(
      with(kCase, "analysis: explicit", "analysis: static"),
      {"case.yaml", 2, 11, "analysis",
       "unknown value 'static' (allowed: explicit, implicit_quasistatic, implicit_dynamic)"});
  expect_error(with(kCase, "dimension: 2", "dimension: 1"),
               {"case.yaml", 3, 12, "dimension", "must be 2 (plane strain) or 3 (got 1)"});
  // A 3D case reads its points with three components: this 2D file's grid fails first.
  expect_error(with(kCase, "dimension: 2", "dimension: 3"),
               {"case.yaml", 5, 11, "grid.origin",
                "expected a 3-element list [x, y, z] (dimension: 3), got a list of 2 elements"});
}

TEST(CaseReaderErrors, DuplicateNames) {
  expect_error(with(kCase, "  - name: rubber", "  - name: disc"),
               {"case.yaml", 14, 11, "materials[1].name",
                "duplicate material name 'disc' (already used by materials[0])"});
  expect_error(with(kCase, "  - name: wedge", "  - name: lower"),
               {"case.yaml", 33, 11, "bodies[2].name",
                "duplicate body name 'lower' (already used by bodies[0])"});
  expect_error(with(kCase, "{name: first, particle: 0}", "{name: tip, particle: 0}"),
               {"case.yaml", 55, 12, "probes[1].name",
                "duplicate probe name 'tip' (already used by probes[0])"});
}

TEST(CaseReaderErrors, BodyRefersToUnknownMaterial) {
  expect_error(with(kCase, "material: rubber", "material: rubbre"),
               {"case.yaml", 27, 15, "bodies[1].material",
                "unknown material 'rubbre' (defined materials: disc, rubber); did you mean "
                "'rubber'?"});
}

TEST(CaseReaderErrors, TractionNeedsAnExistingRectangleBody) {
  expect_error(with(kCase, "{body: upper, side: top", "{body: lower, side: top"),
               {"case.yaml", 45, 12, "tractions[0].body",
                "a traction needs a rectangle body, but body 'lower' is a disc"});
  expect_error(with(kCase, "{body: upper, side: top", "{body: wedge, side: top"),
               {"case.yaml", 45, 12, "tractions[0].body", "body 'wedge' is a polygon"});
  expect_error(with(kCase, "{body: upper, side: top", "{body: beam, side: top"),
               {"case.yaml", 45, 12, "tractions[0].body",
                "unknown body 'beam' (defined bodies: lower, upper, wedge)"});
}

TEST(CaseReaderErrors, KeyOfAnotherShape) {
  expect_error(with(kCase, "    particles_per_cell: 3\n", "    radius: 0.1\n"),
               {"case.yaml", 31, 5, "bodies[1].radius",
                "key 'radius' does not apply to shape rectangle (rectangle takes min, max)"});
  expect_error(
      with(kCase, "    radius: 0.2\n", "    radius: 0.2\n    vertices: [[0, 0]]\n"),
      {"case.yaml", 25, 5, "bodies[0].vertices", "key 'vertices' does not apply to shape disc"});
}

TEST(CaseReaderErrors, ExclusiveKeys) {
  expect_error(with(kCase, "  cfl: 0.5\n", "  cfl: 0.5\n  dt: 1e-4\n"),
               {"case.yaml", 49, 3, "time.dt", "give exactly one of 'cfl' and 'dt', not both"});
  expect_error(with(kCase, "  every_steps: 10\n", "  every_steps: 10\n  every_time: 0.01\n"),
               {"case.yaml", 52, 3, "output.every_time",
                "give at most one of 'every_steps' and 'every_time'"});
  expect_error(
      with(kCase, "{name: first, particle: 0}", "{name: first, particle: 0, point: [0, 0]}"),
      {"case.yaml", 55, 19, "probes[1].particle",
       "give exactly one of 'point' and 'particle', not both"});
  expect_error(with(kCase, "{name: first, particle: 0}", "{name: first}"),
               {"case.yaml", 55, 5, "probes[1]", "missing required key 'point' or 'particle'"});
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

TEST(CaseReaderErrors, VelocityExpressionThatDoesNotParse) {
  expect_error(with(kCase, "velocity: [7, -7]", "velocity: [7, \"2 * * x\"]"),
               {"case.yaml", 25, 19, "bodies[0].velocity[1]", "invalid expression '2 * * x'"});
  expect_error(with(kCase, "velocity: [7, -7]", "velocity: [7, sin(z)]"),
               {"case.yaml", 25, 19, "bodies[0].velocity[1]", "invalid expression 'sin(z)'"});
  // A malformed number is still reported as a number, not as an expression.
  expect_error(with(kCase, "velocity: [7, -7]", "velocity: [7, 1e400]"),
               {"case.yaml", 25, 19, "bodies[0].velocity[1]", "out of the double-precision range"});
}

TEST(CaseReaderErrors, ApicNeedsGimp) {
  expect_error(with(kCase, "  scheme: usf", "  scheme: usf\n  transfer: apic"),
               {"case.yaml", 59, 13, "solver.transfer",
                "transfer 'apic' needs a shape other than 'linear'"});
}

// The boundary-modified splines fold the ghost functions into the two nodes inside each face:
// the cubic ones need three cells on every axis (kMinimal's grid has 4 x 2).
TEST(CaseReaderErrors, BSplinesNeedAStencilOfCellsPerAxis) {
  expect_error(kMinimal + "solver: {shape: bspline3}\n",
               {"case.yaml", 12, 17, "solver.shape",
                "shape 'bspline3' needs at least 3 grid cells along each axis; the grid has 2 "
                "along y"});
  EXPECT_NO_THROW(read_case_text(kMinimal + "solver: {shape: bspline2}\n", "case.yaml"));
}

TEST(CaseReaderErrors, SplinesAreNotAxisymmetric) {
  expect_error(
      "geometry: axisymmetric\n" + kMinimal + "solver: {shape: bspline2}\n",
      {"case.yaml", 13, 17, "solver.shape", "shape 'bspline2' is not available in axisymmetry"});
}

TEST(CaseReaderErrors, CpdiIsNotAxisymmetric) {
  expect_error("geometry: axisymmetric\n" + kMinimal + "solver: {shape: cpdi}\n",
               {"case.yaml", 13, 17, "solver.shape",
                "shape 'cpdi' averages over the deformed "
                "voxel in the plane"});
  const CaseSpec spec =
      read_case_text(kCase, "case.yaml", {"solver.shape=gimp", "solver.transfer=apic"});
  EXPECT_EQ(spec.solver.transfer, TransferScheme::Apic);
}

// Plastic material keys: a key of another model is refused by name, the model's own checks
// report at the key they concern, and a symmetric-only linear solver is refused for a
// nonsymmetric tangent.
TEST(CaseReaderErrors, PlasticMaterialKeys) {
  expect_error(with(kCase, "poisson_ratio: 0.3", "poisson_ratio: 0.3\n    cohesion: 1.0e4"),
               {"case.yaml", 14, 5, "materials[0].cohesion",
                "'cohesion' does not apply to model 'linear_elastic' (an elastic model)"});
  const std::string mc = with(kCase, "model: linear_elastic", "model: mohr_coulomb");
  expect_error(with(mc, "poisson_ratio: 0.3",
                    "poisson_ratio: 0.3\n    cohesion: 1.0e4\n    friction_angle: 20\n"
                    "    dilation_angle: 30"),
               {"case.yaml", 16, 21, "materials[0].dilation_angle", "dilation"});
  expect_error(with(mc, "poisson_ratio: 0.3", "poisson_ratio: 0.3\n    cohesion: 1.0e4"),
               {"case.yaml", 9, 5, "materials[0]", "missing required key 'friction_angle'"});
}

// f_bar belongs to the implicit grid solve, and its tangent is nonsymmetric: an explicit case
// and a symmetric-only linear solver are refused at the key.
TEST(CaseReaderErrors, FBarNeedsAnImplicitAnalysisAndANonsymmetricSolver) {
  const std::string f_bar = with(kCase, "  flip: 0.95", "  flip: 0.95\n  f_bar: true");
  expect_error(f_bar, {"case.yaml", 60, 3, "solver.f_bar", "explicit analyses do not support it"});
  const std::string implicit =
      with(with(f_bar, "analysis: explicit", "analysis: implicit_quasistatic"), "  cfl: 0.5",
           "  dt: 0.01");
  EXPECT_TRUE(read_case_text(implicit, "case.yaml").solver.f_bar);
  expect_error(with(implicit, "  f_bar: true", "  f_bar: true\n  linear_solver: cholmod"),
               {"case.yaml", 61, 18, "solver.linear_solver",
                "'cholmod' needs a symmetric tangent, but f_bar couples the points of a cell"});
}

// f_bar_out_of_plane chooses plane strain's F-bar: without F-bar it would do nothing, and in 3D
// (and axisymmetry) F-bar always spreads over three axes.
TEST(CaseReaderErrors, FBarOutOfPlaneIsPlaneStrainsChoice) {
  const std::string implicit =
      with(with(with(kCase, "analysis: explicit", "analysis: implicit_quasistatic"), "  cfl: 0.5",
                "  dt: 0.01"),
           "  flip: 0.95", "  flip: 0.95\n  f_bar_out_of_plane: true");
  expect_error(implicit, {"case.yaml", 60, 23, "solver.f_bar_out_of_plane",
                          "has no effect without 'f_bar: true'"});
  const std::string spread =
      with(implicit, "  f_bar_out_of_plane", "  f_bar: true\n  f_bar_out_of_plane");
  EXPECT_TRUE(read_case_text(spread, "case.yaml").solver.f_bar_out_of_plane);
  const std::string slab = R"(name: slab
analysis: implicit_quasistatic
dimension: 3
grid: {origin: [0, 0, 0], extent: [1, 1, 1], cell_size: 0.25}
materials:
  - {name: m, model: linear_elastic, density: 1000, youngs_modulus: 1.0e6, poisson_ratio: 0.3}
bodies:
  - {name: b, material: m, shape: box, min: [0, 0, 0], max: [1, 0.5, 1]}
gravity: [0, -10, 0]
boundaries: {y_min: fixed}
time: {end_time: 1, dt: 1}
solver: {f_bar: true, f_bar_out_of_plane: true}
)";
  expect_error(slab, {"case.yaml", 12, 23, "solver.f_bar_out_of_plane",
                      "in 3D and axisymmetry F-bar always spreads the volume change over three"});
}

// The step-growth threshold counts Newton iterations, so it cannot exceed their limit.
TEST(CaseReaderErrors, EasyNewtonIterationsStayWithinTheLimit) {
  const std::string easy = with(kCase, "  flip: 0.95",
                                "  flip: 0.95\n  max_newton_iterations: 10\n"
                                "  easy_newton_iterations: 11");
  expect_error(easy, {"case.yaml", 61, 27, "solver.easy_newton_iterations",
                      "must be an integer in [1, max_newton_iterations = 10] (got 11)"});
  EXPECT_EQ(read_case_text(with(easy, "iterations: 11", "iterations: 6"), "case.yaml")
                .solver.easy_newton_iterations,
            6);
  EXPECT_EQ(read_case_text(kCase, "case.yaml").solver.easy_newton_iterations, 4);
}

// plastic_strain is a field of the elasto-plastic models: asking for it in an all-elastic case
// is an error at the list item; with a plastic material it is accepted, and on by default.
TEST(CaseReaderErrors, PlasticStrainFieldNeedsAPlasticMaterial) {
  const std::string asks =
      with(kCase, "fields: [velocity, F, stress]", "fields: [velocity, F, plastic_strain]");
  expect_error(asks, {"case.yaml", 52, 25, "output.fields[2]",
                      "field 'plastic_strain' needs an elasto-plastic material"});
  const std::string tresca = with(kCase, "model: linear_elastic", "model: tresca\n    cohesion: 5");
  EXPECT_EQ(read_case_text(with(tresca, "fields: [velocity, F, stress]",
                                "fields: [velocity, F, plastic_strain]"),
                           "case.yaml")
                .output.fields,
            (std::vector<OutputField>{OutputField::Velocity, OutputField::DeformationGradient,
                                      OutputField::PlasticStrain}));
  const std::string no_fields = "  fields: [velocity, F, stress]\n";
  const std::vector<OutputField> defaults =
      read_case_text(with(tresca, no_fields, ""), "case.yaml").output.fields;
  EXPECT_EQ(defaults.size(), 7u);
  EXPECT_EQ(defaults.back(), OutputField::PlasticStrain);
  EXPECT_EQ(read_case_text(with(kCase, no_fields, ""), "case.yaml").output.fields.size(), 6u);
}

} // namespace
} // namespace talus

namespace talus {
namespace {

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

TEST(CaseReaderErrors, SplitValues) {
  const std::string file =
      with(kCase, "    velocity: [7, -7]\n", "    velocity: [7, -7]\n    split: {alpha: 0.5}\n");
  expect_error(file, {"case.yaml", 26, 20, "bodies[0].split.alpha", "must be > 1"});
  const struct {
    std::string set, key, message;
  } bad[] = {
      {"beta: 1", "beta", "must be in the open interval (0, 1)"},
      {"beta: 0", "beta", "must be in the open interval (0, 1)"},
      {"gamma: 0", "gamma", "must be > 0"},
      {"max_generations: 31", "max_generations", "must be an integer from 0 to 30"},
      {"max_generations: -1", "max_generations", "must be an integer from 0 to 30"},
      {"max_generations: 1.5", "max_generations", "integer"},
      {"min_size: -0.1", "min_size", "must be >= 0"},
      {"alpha: .nan", "alpha", "finite"},
      {"delta: 1", "delta", "unknown key 'delta'"},
  };
  for (const auto& b : bad)
    expect_error(kCase, {"--set", 0, 0, "bodies[0].split." + b.key, b.message},
                 {"bodies.lower.split={" + b.set + "}"});
}

// output.checkpoint: every_steps a count, every_seconds positive, at least one of them.
TEST(CaseReaderErrors, CheckpointNeedsAScheduleOfCountsOrSeconds) {
  const CaseSpec c = read_case_text(
      kMinimal + "output: {checkpoint: {every_steps: 50, every_seconds: 600}}\n", "case.yaml");
  ASSERT_TRUE(c.output.checkpoint.has_value());
  EXPECT_EQ(c.output.checkpoint->every_steps, 50);
  EXPECT_EQ(c.output.checkpoint->every_seconds, 600.0);
  EXPECT_FALSE(read_case_text(kMinimal, "case.yaml").output.checkpoint.has_value());
  expect_error(
      kMinimal + "output: {checkpoint: {every_steps: 0}}\n",
      {"case.yaml", 12, 36, "output.checkpoint.every_steps", "must be an integer >= 1 (got 0)"});
  expect_error(kMinimal + "output: {checkpoint: {every_seconds: -1}}\n",
               {"case.yaml", 12, 38, "output.checkpoint.every_seconds", "-1"});
  expect_error(
      kMinimal + "output: {checkpoint: {}}\n",
      {"case.yaml", 12, 22, "output.checkpoint", "give 'every_steps', 'every_seconds' or both"});
  expect_error(kMinimal + "output: {checkpoint: {every_step: 5}}\n",
               {"case.yaml", 12, 23, "output.checkpoint.every_step", "every_steps"});
}

} // namespace
} // namespace talus
