// Case-file reader: every error class with its exact location (file, line, column, key).
#include "case_reader_fixtures.hpp"

#include "talus/io/case_reader.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

namespace talus {
namespace {

using namespace case_reader_test;

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
                      "unit_weight, youngs_modulus, poisson_ratio, kinematics, yield_stress, "
                      "hardening_modulus, cohesion, friction_angle, dilation_angle, residual, "
                      "saturated_density, saturated_unit_weight, permeability, biot_coefficient, "
                      "biot_modulus, fluid_bulk_modulus, porosity); did you mean "
                      "'youngs_modulus'?"});
  // Exact full message (format comes from SourceLocation::to_string()).
  try {
    read_case_text(text, "case.yaml");
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "case.yaml:12:5: key 'materials[0].youngs_modolus': unknown key "
                           "'youngs_modolus' (allowed keys here: name, model, density, "
                           "unit_weight, youngs_modulus, poisson_ratio, kinematics, yield_stress, "
                           "hardening_modulus, cohesion, friction_angle, dilation_angle, "
                           "residual, saturated_density, saturated_unit_weight, permeability, "
                           "biot_coefficient, biot_modulus, fluid_bulk_modulus, porosity); did "
                           "you mean 'youngs_modulus'?");
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
                "unknown value 'clamped' (allowed: free, fixed, roller, platen)"});
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
       "pore_pressure, effective_stress, reference_position)"});
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
