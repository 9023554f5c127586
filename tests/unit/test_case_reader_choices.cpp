// Case-file reader: the errors of solver, shape and material choices that do not go together
// (APIC without GIMP, splines in axisymmetry, F-bar with a symmetric solver, ...), each at its
// key; velocity expressions that do not parse.
#include "case_reader_fixtures.hpp"

#include "talus/io/case_reader.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace talus {
namespace {

using namespace case_reader_test;

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
