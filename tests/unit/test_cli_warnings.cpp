// Plausibility warnings and the geotechnical vocabulary (issue 39) through the real `talus`
// binary: each implausible magnitude gets a warning at its key naming the likely mistake, the
// run goes on, and `silence_warnings` accepts it; loads that reach no material, and the new
// keys used wrongly, are input errors (exit 2).
#include "talus/io/case_reader.hpp"

#include "cli_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

using namespace talus::test_support;

namespace {

// A 4 m x 2 m block of Mohr-Coulomb soil under gravity with a footing box on its surface: every
// magnitude plausible, so no warning. Line 1 is "name: ...".
const std::string kCase = R"(name: warnings
analysis: implicit_quasistatic
grid: {origin: [0, 0], extent: [4, 3], cell_size: 0.5}
gravity: [0, -9.81]
materials:
  - name: clay
    model: mohr_coulomb
    density: 2000
    youngs_modulus: 2.0e7
    poisson_ratio: 0.3
    cohesion: 1.0e4
    friction_angle: 30
bodies:
  - {name: block, material: clay, shape: rectangle, min: [0, 0], max: [4, 2], particles_per_cell: 2}
boundaries: {x_min: roller, x_max: roller, y_min: fixed}
prescribed:
  - {name: footing, min: [0, 2], max: [1, 2], displacement: [~, -0.01]}
time: {end_time: 1, dt: 0.5}
)";

std::string edited(const std::string& from, const std::string& to, std::string text = kCase) {
  return replaced_once(from, to, std::move(text));
}

/// How often `needle` occurs in `text`.
int count(const std::string& text, const std::string& needle) {
  int n = 0;
  for (auto at = text.find(needle); at != std::string::npos; at = text.find(needle, at + 1))
    ++n;
  return n;
}

struct Implausible {
  std::string label;
  std::string text;
  std::string check;                 // the word that silences it
  std::vector<std::string> expected; // substrings of stderr: the key and the likely mistake
};

class CliWarnings : public Cli {
protected:
  Outcome check(const std::string& text) {
    write_file(work() / "case.yaml", text);
    return talus({"check", "case.yaml"});
  }
};

TEST_F(CliWarnings, APlausibleCaseHasNoWarning) {
  const Outcome r = check(kCase);
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.describe();
}

TEST_F(CliWarnings, EachCheckWarnsAtItsKeyAndCanBeSilenced) {
  const std::vector<Implausible> cases = {
      {"a density in t/m^3",
       edited("density: 2000", "density: 2"),
       "density",
       {"case.yaml:8:14: key 'materials[0].density'", "density of 2 kg/m^3", "t/m^3?"}},
      {"a unit weight typed as a density",
       edited("density: 2000", "density: 18000"),
       "density",
       {"key 'materials[0].density'", "a unit weight typed as a density?",
        "write unit_weight: 18000"}},
      {"a unit weight in kN/m^3",
       edited("density: 2000", "unit_weight: 18"),
       "density",
       {"case.yaml:8:18: key 'materials[0].unit_weight'", "kN/m^3? Talus takes N/m^3"}},
      {"a saturated density in t/m^3",
       edited("density: 2000", "density: 2000\n    saturated_density: 2.1") + "water: {level: 1}\n",
       "density",
       {"key 'materials[0].saturated_density'", "density of 2.1 kg/m^3", "t/m^3?"}},
      {"E = 20 meant as 20 MPa",
       edited("youngs_modulus: 2.0e7", "youngs_modulus: 20"),
       "youngs_modulus",
       {"case.yaml:9:21: key 'materials[0].youngs_modulus'", "far below the softest soils",
        "Talus takes pascals, so 20 MPa is 2e+07"}},
      {"a body that its own weight would halve",
       edited("density: 2000", "density: 5000",
              edited("youngs_modulus: 2.0e7", "youngs_modulus: 1.5e5")),
       "youngs_modulus",
       {"key 'materials[0].youngs_modulus'", "rho g H = 98.1 kPa",
        "would sink under its own weight"}},
      {"a cohesion typed in kPa",
       edited("cohesion: 1.0e4", "cohesion: 10"),
       "strength",
       {"case.yaml:11:15: key 'materials[0].cohesion'", "cohesion of 10 Pa", "rho g H = 39.2 kPa",
        "typed in kPa? Talus takes pascals, so 10 kPa is 10000"}},
      {"a cohesion near E",
       edited("cohesion: 1.0e4", "cohesion: 5.0e6"),
       "strength",
       {"key 'materials[0].cohesion'", "0.25 of its Young's modulus", "are both in Pa?"}},
      {"a friction angle in radians",
       edited("friction_angle: 30", "friction_angle: 0.5"),
       "friction_angle",
       {"case.yaml:12:21: key 'materials[0].friction_angle'", "radians?", "28.6 degrees"}},
      {"a friction angle above any soil",
       edited("friction_angle: 30", "friction_angle: 70"),
       "friction_angle",
       {"key 'materials[0].friction_angle'", "above any soil"}},
      {"a traction above E",
       kCase + "tractions:\n  - {body: block, side: top, traction: [0, -1.0e8]}\n",
       "load",
       {"key 'tractions[0].traction'", "above the Young's modulus", "is the traction in Pa?"}},
      {"a point load of 20 MN/m on a 0.5 m cell",
       kCase + "point_loads:\n  - {name: pile, point: [2, 2], force: [0, -2.0e7]}\n",
       "load",
       {"key 'point_loads[0].force'", "point load 'pile' spread over a cell face (0.5 m) is",
        "is the force in N"}},
      {"gravity in mm/s^2",
       edited("gravity: [0, -9.81]", "gravity: [0, -9810]"),
       "gravity",
       {"case.yaml:4:10: key 'gravity'", "gravity is 9810 m/s^2"}},
      {"an intrinsic permeability in m^2 for k in m/s",
       edited("friction_angle: 30", "friction_angle: 30\n    permeability: 1.0e-16") +
           "water: {unit_weight: 9810, level: 2}\n",
       "permeability",
       {"case.yaml:13:19: key 'materials[0].permeability'", "permeability 1e-16 m/s",
        "not an intrinsic permeability in m^2"}},
      {"a consolidation loaded in steps below h^2 / (6 c_v)",
       edited("time: {end_time: 1, dt: 0.5}", "time: {end_time: 1.0e-4, dt: 1.0e-4}",
              edited("friction_angle: 30", "friction_angle: 30\n    permeability: 1.0e-3")) +
           "water: {unit_weight: 9810, level: 2}\n",
       "consolidation_step",
       {"key 'time.dt'", "the loads change in steps of 0.0001 s, shorter than h^2 / (6 c_v)",
        "of material 'clay'"}},
      {"a consolidation case whose modulus is a denormal 1e-310 Pa (1 / M_c overflows)",
       edited("youngs_modulus: 2.0e7\n    poisson_ratio: 0.3",
              "youngs_modulus: 1e-310\n    poisson_ratio: 0",
              edited("friction_angle: 30", "friction_angle: 30\n    permeability: 1.0e-3")) +
           "water: {unit_weight: 9810, level: 2}\n",
       "youngs_modulus",
       {"key 'materials[0].youngs_modulus'"}},
      {"a settlement in mm",
       edited("displacement: [~, -0.01]", "displacement: [~, -35]"),
       "displacement",
       {"key 'prescribed[0].displacement'", "moves by -35 m along y", "-35 mm is -0.035 m"}},
  };
  for (const Implausible& c : cases) {
    SCOPED_TRACE(c.label);
    const std::string accept = "silence_warnings: [" + c.check + "]";
    const Outcome r = check(c.text);
    EXPECT_EQ(r.exit_code, 0) << r.describe();
    EXPECT_GE(count(r.err, "talus: warning: "), 1) << r.describe();
    EXPECT_GE(count(r.err, accept), 1) << r.describe();
    for (const std::string& part : c.expected)
      EXPECT_NE(r.err.find(part), std::string::npos) << "stderr lacks \"" << part << "\"\n"
                                                     << r.describe();
    const Outcome silenced = check(c.text + accept + "\n");
    EXPECT_EQ(silenced.exit_code, 0) << silenced.describe();
    EXPECT_EQ(count(silenced.err, accept), 0) << silenced.describe();
  }
}

TEST_F(CliWarnings, ARunPrintsTheWarningsAndGoesOn) {
  write_file(work() / "case.yaml", edited("cohesion: 1.0e4", "cohesion: 10"));
  const Outcome r = talus({"run", "case.yaml", "--out", "out"});
  EXPECT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_EQ(count(r.err, "talus: warning: "), 1) << r.describe();
  EXPECT_NE(r.err.find("typed in kPa?"), std::string::npos) << r.describe();
}

TEST_F(CliWarnings, AnUnknownCheckIsRefusedWithItsNeighbour) {
  const Outcome r = check(kCase + "silence_warnings: [strenght]\n");
  EXPECT_EQ(r.exit_code, 2) << r.describe();
  EXPECT_NE(r.err.find("case.yaml:19:20: key 'silence_warnings[0]': unknown value 'strenght'"),
            std::string::npos)
      << r.describe();
  EXPECT_NE(r.err.find("did you mean 'strength'?"), std::string::npos) << r.describe();
}

struct Refused {
  std::string label;
  std::string text;
  std::vector<std::string> expected;
};

TEST_F(CliWarnings, LoadsThatReachNoMaterialAndMisusedKeysAreErrors) {
  const std::string far_load = "point_loads:\n  - {name: far, point: [2, 2.9], force: [0, -1]}\n";
  const std::vector<Refused> cases = {
      {"a footing box above the surface",
       edited("min: [0, 2], max: [1, 2]", "min: [0, 3], max: [1, 3]"),
       {"case.yaml:17:26: key 'prescribed[0].min'", "prescribed box 'footing' reaches no material",
        "the nearest point is 1.12 m from the box, [0, 2.99] to [1, 3]"}},
      {"a point load above the surface",
       kCase + far_load,
       {"key 'point_loads[0].point'", "point load 'far' at [2, 2.9] reaches no material",
        "1.03 m away"}},
      {"unit_weight without gravity",
       edited("gravity: [0, -9.81]\n", "", edited("density: 2000", "unit_weight: 18000")),
       {"case.yaml:7:18: key 'materials[0].unit_weight': unit_weight needs gravity"}},
      {"both density and unit_weight",
       edited("density: 2000", "density: 2000\n    unit_weight: 18000"),
       {"key 'materials[0].unit_weight': give either density (kg/m^3) or unit_weight"}},
      {"k0: jaky without a friction angle",
       edited("    friction_angle: 30\n", "",
              edited("model: mohr_coulomb", "model: tresca",
                     edited("particles_per_cell: 2}",
                            "particles_per_cell: 2,\n     initial_stress: {type: geostatic, k0: "
                            "jaky}}"))),
       {"key 'bodies[0].initial_stress.k0': k0: jaky needs a friction angle"}},
  };
  for (const Refused& c : cases) {
    SCOPED_TRACE(c.label);
    for (const char* command : {"check", "run"}) {
      SCOPED_TRACE(command);
      write_file(work() / "case.yaml", c.text);
      std::vector<std::string> args{command, "case.yaml"};
      if (std::string(command) == "run")
        args.insert(args.end(), {"--out", "out"});
      const Outcome r = talus(args);
      EXPECT_EQ(r.exit_code, 2) << r.describe();
      for (const std::string& part : c.expected)
        EXPECT_NE(r.err.find(part), std::string::npos) << "stderr lacks \"" << part << "\"\n"
                                                       << r.describe();
      EXPECT_FALSE(fs::exists(work() / "out")) << r.describe();
    }
  }
  // The other side of each bound: a box that reaches the surface only along its displacement,
  // and a point load on the surface, are accepted.
  for (const std::string& text :
       {edited("min: [0, 2], max: [1, 2], displacement: [~, -0.01]",
               "min: [0, 3], max: [1, 3], displacement: [~, -1.0]"),
        kCase + "point_loads:\n  - {name: near, point: [2, 2.0], force: [0, -1]}\n"}) {
    const Outcome r = check(text);
    EXPECT_EQ(r.exit_code, 0) << r.describe();
  }
}

// talus check names the linear solver the run will use, from the tangent's symmetry: a
// non-associated Mohr-Coulomb soil (psi = 0 < phi) needs LU, an associated one Cholesky.
TEST_F(CliWarnings, CheckNamesTheLinearSolverAndARoughRunTime) {
  write_file(work() / "case.yaml", kCase);
  const Outcome lu = talus({"check", "case.yaml", "--threads", "2"});
  ASSERT_EQ(lu.exit_code, 0) << lu.describe();
  for (const char* part : {"solver    umfpack (nonsymmetric tangent), about ", " unknowns",
                           "run time  under a second (2 load steps of ", "on 2 threads"})
    EXPECT_NE(lu.out.find(part), std::string::npos) << part << "\n" << lu.describe();
  const Outcome cholesky =
      talus({"check", "case.yaml", "--set", "materials.clay.dilation_angle=30"});
  EXPECT_NE(cholesky.out.find("solver    cholmod (symmetric tangent)"), std::string::npos)
      << cholesky.describe();
}

// unit_weight is gamma = rho |g| exactly, and Jaky's K0 is 1 - sin(phi).
TEST(GeotechnicalVocabulary, UnitWeightAndJaky) {
  const talus::CaseSpec weight = talus::read_case_text(
      edited("density: 2000", "unit_weight: 18000",
             edited("particles_per_cell: 2}",
                    "particles_per_cell: 2,\n     initial_stress: {type: geostatic, k0: jaky}}")),
      "case.yaml");
  EXPECT_DOUBLE_EQ(weight.materials[0].density * 9.81, 18000.0);
  ASSERT_TRUE(weight.bodies[0].initial_stress && weight.bodies[0].initial_stress->k0);
  EXPECT_DOUBLE_EQ(*weight.bodies[0].initial_stress->k0,
                   1.0 - std::sin(30.0 * std::numbers::pi / 180.0));
}

} // namespace
