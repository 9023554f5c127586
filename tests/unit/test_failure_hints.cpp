// Numerical failures that name their cause (issue 39): the likely causes a failed run lists,
// read from the case, and the messages of real failed runs through the `talus` binary.
#include "talus/io/case_reader.hpp"
#include "talus/solver/failure_hints.hpp"

#include "cli_support.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

using namespace talus;
using namespace talus::test_support;

namespace {

// A block of Mohr-Coulomb soil on a fixed base, loaded by its weight; line 1 is "name: ...".
const std::string kCase = R"(name: failing
analysis: implicit_quasistatic
grid: {origin: [0, 0], extent: [4, 3], cell_size: 0.5}
gravity: [0, -9.81]
materials:
  - {name: clay, model: mohr_coulomb, density: 2000, youngs_modulus: 2.0e7, poisson_ratio: 0.3,
     cohesion: 1.0e4, friction_angle: 30}
bodies:
  - {name: block, material: clay, shape: rectangle, min: [0, 0], max: [4, 2], particles_per_cell: 2}
boundaries: {x_min: roller, x_max: roller, y_min: fixed}
time: {end_time: 1, dt: 0.5}
)";

std::string edited(const std::string& from, const std::string& to, std::string text = kCase) {
  return replaced_once(from, to, std::move(text));
}

std::string causes_of(const std::string& text, FailureContext context) {
  return describe_likely_causes(likely_failure_causes(read_case_text(text, "case.yaml"), context));
}

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST(FailureHints, EachCauseIsNamedOnlyWhenTheCaseSuggestsIt) {
  const FailureContext quasi_static{AnalysisType::ImplicitQuasistatic, false};
  const FailureContext stalled{AnalysisType::ImplicitQuasistatic, true};
  // A plausible, supported case that failed without a stall suggests nothing.
  EXPECT_EQ(causes_of(kCase, quasi_static), "");
  const std::string units =
      causes_of(edited("youngs_modulus: 2.0e7", "youngs_modulus: 20"), quasi_static);
  EXPECT_TRUE(has(units, "Likely causes: (1) a unit mistake: materials[0].youngs_modulus, "
                         "materials[0].cohesion are far from any soil or rock"))
      << units;
  const std::string free = causes_of(
      edited("{x_min: roller, x_max: roller, y_min: fixed}", "{x_min: free}"), quasi_static);
  EXPECT_TRUE(has(free, "body 'block' touches no fixed or roller face and no prescribed box"))
      << free;
  // A fixed face the body does not reach holds nothing either.
  const std::string far_face = causes_of(
      edited("{x_min: roller, x_max: roller, y_min: fixed}", "{y_max: fixed}"), quasi_static);
  EXPECT_TRUE(has(far_face, "body 'block' touches no fixed")) << far_face;
  EXPECT_TRUE(has(causes_of(kCase, stalled), "the load has reached the soil's limit"));
  const std::string dynamic = causes_of(kCase, {AnalysisType::ImplicitDynamic, false});
  EXPECT_TRUE(has(dynamic, "lower time.dt")) << dynamic;
  // The explicit hint names the case's own CFL number.
  const std::string explicit_case =
      edited("analysis: implicit_quasistatic", "analysis: explicit",
             edited("time: {end_time: 1, dt: 0.5}", "time: {end_time: 1, cfl: 0.8}"));
  const std::string fast = causes_of(explicit_case, {AnalysisType::Explicit, false});
  EXPECT_TRUE(has(fast, "lower time.cfl (now 0.8)")) << fast;
}

class FailedRuns : public Cli {};

// The issue's first example: E = 20 meant as 20 MPa, under a footing. The run still fails
// (exit 3), and the message names the material, the point, where it is and the quantity of the
// trial state Newton could not use, and the unit mistake.
TEST_F(FailedRuns, AModulusInTheWrongUnitIsNamed) {
  const std::string footing =
      "prescribed:\n  - {name: footing, min: [0, 2], max: [1, 2], displacement: [~, -0.01]}\n";
  write_file(work() / "case.yaml", edited("youngs_modulus: 2.0e7", "youngs_modulus: 20") + footing);
  const Outcome r = talus({"run", "case.yaml", "--out", "out"});
  EXPECT_EQ(r.exit_code, 3) << r.describe();
  for (const char* part :
       {"Newton did not converge at the minimum load step",
        "the last trial state Newton could not use: material 'clay', point ",
        ": Mohr-Coulomb: det F = ", "is not positive (the point at [", "in body 'block')",
        "Likely causes: (1) a unit mistake: materials[0].youngs_modulus, materials[0].cohesion "
        "are far from any soil or rock"})
    EXPECT_TRUE(has(r.err, part)) << "stderr lacks \"" << part << "\"\n" << r.describe();
}

// Without the footing the soft block sinks through its base: the failure names the point too.
TEST_F(FailedRuns, APointThatLeavesTheGridIsNamedWithTheUnitMistake) {
  write_file(work() / "case.yaml", edited("youngs_modulus: 2.0e7", "youngs_modulus: 20"));
  const Outcome r = talus({"run", "case.yaml", "--out", "out"});
  EXPECT_EQ(r.exit_code, 3) << r.describe();
  for (const char* part : {"left the grid", "Likely causes: (1) a unit mistake: "
                                            "materials[0].youngs_modulus"})
    EXPECT_TRUE(has(r.err, part)) << "stderr lacks \"" << part << "\"\n" << r.describe();
}

// A body nothing holds makes the quasi-static tangent singular; the message says so.
TEST_F(FailedRuns, AnUnsupportedBodyIsNamed) {
  write_file(work() / "case.yaml",
             edited("{x_min: roller, x_max: roller, y_min: fixed}", "{x_min: free}"));
  const Outcome r = talus({"run", "case.yaml", "--out", "out"});
  EXPECT_EQ(r.exit_code, 3) << r.describe();
  EXPECT_TRUE(has(r.err, "body 'block' touches no fixed or roller face and no prescribed box: "
                         "nothing holds it against rigid motion"))
      << r.describe();
}

// A zero or negative pivot names its unknown: the node, the component and its stiffness. An
// elastic block that nothing holds has a tangent with rigid-body modes; Cholesky meets the first
// of them as a non-positive pivot (measured: -1.5e-7 against a largest diagonal of 4.3e7).
TEST_F(FailedRuns, ASingularTangentNamesItsNode) {
  const std::string elastic =
      edited("  - {name: clay, model: mohr_coulomb, density: 2000, youngs_modulus: 2.0e7, "
             "poisson_ratio: 0.3,\n     cohesion: 1.0e4, friction_angle: 30}",
             "  - {name: clay, model: linear_elastic, density: 2000, youngs_modulus: 2.0e7, "
             "poisson_ratio: 0.3}");
  write_file(work() / "case.yaml",
             edited("{x_min: roller, x_max: roller, y_min: fixed}", "{}",
                    edited("max: [4, 2]", "max: [3.5, 2]",
                           edited("min: [0, 0], max", "min: [0.5, 0.5], max", elastic))) +
                 "solver: {linear_solver: cholmod}\n");
  const Outcome r = talus({"run", "case.yaml", "--out", "out"});
  EXPECT_EQ(r.exit_code, 3) << r.describe();
  for (const char* part :
       {"cholmod: matrix is not positive definite (the pivot of column ", ": unknown ",
        " displacement of the grid node at [", "whose diagonal stiffness is ",
        "Likely causes: (1) body 'block' touches no fixed or roller face"})
    EXPECT_TRUE(has(r.err, part)) << "stderr lacks \"" << part << "\"\n" << r.describe();
}

} // namespace
