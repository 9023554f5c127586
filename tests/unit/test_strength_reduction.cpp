// Strength reduction (talus fos): the case section, the weakened materials, the bisection with a
// fake trial whose critical factor is known, and one small search end to end.
#include "talus/core/errors.hpp"
#include "talus/io/case_reader.hpp"
#include "talus/solver/strength_reduction.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

namespace fs = std::filesystem;
using namespace talus;

namespace {

// A coarse 2:1 slope (Griffiths & Lane's shape, 2 m cells): cheap enough for a unit test.
const std::string kSlope = R"(name: small_slope
analysis: implicit_quasistatic
grid: {origin: [0, 0], extent: [40, 12], cell_size: 2}
materials:
  - {name: soil, model: mohr_coulomb, density: 2000, youngs_modulus: 1.0e8, poisson_ratio: 0.3,
     cohesion: 1.0e4, friction_angle: 20, dilation_angle: 5,
     residual: {cohesion: 5.0e3, friction_angle: 15, plastic_strain: 0.1}}
  - {name: rock, model: linear_elastic, density: 2500, youngs_modulus: 1.0e9, poisson_ratio: 0.2}
bodies:
  - {name: slope, material: soil, shape: polygon, vertices: [[0, 0], [32, 0], [12, 10], [0, 10]]}
gravity: [0, -10]
boundaries: {x_min: roller, y_min: fixed}
time: {end_time: 1, dt: 0.5, min_dt: 0.125, max_steps: 50}
output: {every_steps: 1}
probes:
  - {name: crest, point: [12, 10]}
strength_reduction: {lower: 1.0, upper: 4.0, tolerance: 0.5, probe: crest}
)";

std::string with(const std::string& text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << "test bug: '" << from << "' not in the case text";
  std::string out = text;
  if (at != std::string::npos)
    out.replace(at, from.size(), to);
  return out;
}

std::string error_of(const std::string& text) {
  try {
    read_case_text(text, "case.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

/// A trial that fails exactly at and above `critical`.
StrengthTrial fake_trial(double factor, double critical) {
  StrengthTrial t;
  t.factor = factor;
  t.failed = factor >= critical;
  t.reason = t.failed ? "failed" : "stood";
  return t;
}

} // namespace

TEST(StrengthReduction, ReadsTheSectionWithDefaults) {
  const CaseSpec spec = read_case_text(kSlope, "case.yaml");
  ASSERT_TRUE(spec.strength_reduction);
  EXPECT_DOUBLE_EQ(spec.strength_reduction->lower, 1.0);
  EXPECT_DOUBLE_EQ(spec.strength_reduction->upper, 4.0);
  EXPECT_DOUBLE_EQ(spec.strength_reduction->tolerance, 0.5);
  EXPECT_EQ(spec.strength_reduction->max_trials, 16);
  EXPECT_EQ(spec.strength_reduction->probe, "crest");
  EXPECT_FALSE(spec.strength_reduction->displacement_limit);
  const CaseSpec limited = read_case_text(
      with(kSlope, "probe: crest}", "probe: crest, displacement_limit: 0.5}"), "case.yaml");
  EXPECT_DOUBLE_EQ(*limited.strength_reduction->displacement_limit, 0.5);
}

TEST(StrengthReduction, RefusesSectionsItCannotSearch) {
  EXPECT_NE(error_of(with(kSlope, "probe: crest}", "probe: toe}")).find("no probe named 'toe'"),
            std::string::npos);
  EXPECT_NE(error_of(with(kSlope, ", probe: crest}", "}")).find("missing required key 'probe'"),
            std::string::npos);
  EXPECT_NE(error_of(with(kSlope, "upper: 4.0", "upper: 0.5")).find("must be above 'lower'"),
            std::string::npos);
  EXPECT_NE(error_of(with(kSlope, "tolerance: 0.5", "max_trials: 1")).find("[2, 100]"),
            std::string::npos);
  EXPECT_NE(error_of(with(kSlope, "analysis: implicit_quasistatic", "analysis: implicit_dynamic"))
                .find("needs 'analysis: implicit_quasistatic'"),
            std::string::npos);
  std::string elastic = with(kSlope, "model: mohr_coulomb", "model: linear_elastic");
  elastic = with(elastic,
                 "cohesion: 1.0e4, friction_angle: 20, dilation_angle: 5,\n"
                 "     residual: {cohesion: 5.0e3, friction_angle: 15, plastic_strain: 0.1}}",
                 "}");
  EXPECT_NE(error_of(elastic).find("no tresca, mohr_coulomb or drucker_prager material"),
            std::string::npos);
}

TEST(StrengthReduction, DividesCohesionAndTanPhiAndCapsDilation) {
  const CaseSpec spec = read_case_text(kSlope, "case.yaml");
  const double F = 2.0;
  const CaseSpec reduced = reduce_strength(spec, F);
  const double degree = std::numbers::pi / 180.0;
  const MaterialSpec& soil = reduced.materials[0];
  EXPECT_DOUBLE_EQ(soil.cohesion, 5.0e3);
  EXPECT_NEAR(std::tan(soil.friction_angle * degree), std::tan(20 * degree) / F, 1e-14);
  EXPECT_DOUBLE_EQ(soil.dilation_angle, 5.0); // below the reduced phi: a flow parameter, kept
  EXPECT_DOUBLE_EQ(soil.residual->cohesion, 2.5e3);
  EXPECT_NEAR(std::tan(soil.residual->friction_angle * degree), std::tan(15 * degree) / F, 1e-14);
  // psi above the reduced phi (here the residual one) is capped: the models require psi <= phi.
  const MaterialSpec weak = reduce_strength(spec, 4.0).materials[0];
  EXPECT_DOUBLE_EQ(weak.dilation_angle, weak.residual->friction_angle);
  // Elastic materials keep their parameters.
  EXPECT_DOUBLE_EQ(reduced.materials[1].youngs_modulus, spec.materials[1].youngs_modulus);
}

TEST(StrengthReduction, BisectionBracketsTheCriticalFactor) {
  StrengthReductionSpec settings;
  settings.lower = 1.0;
  settings.upper = 2.0;
  settings.tolerance = 0.01;
  int seen = 0;
  const FactorOfSafety fos = search_factor_of_safety(
      settings, [](double F) { return fake_trial(F, 1.437); },
      [&](const StrengthTrial&) { ++seen; });
  ASSERT_TRUE(fos.bracketed) << fos.message;
  EXPECT_LE(fos.lower, 1.437);
  EXPECT_GE(fos.upper, 1.437);
  EXPECT_LE(fos.upper - fos.lower, 0.01);
  // lower, upper, then bisections of a width-1 bracket down to 1/128 < 0.01.
  EXPECT_EQ(fos.trials.size(), 9u);
  EXPECT_EQ(seen, 9);
}

TEST(StrengthReduction, RaisesTheUpperFactorWhileItStands) {
  StrengthReductionSpec settings;
  settings.tolerance = 0.05;
  const FactorOfSafety fos =
      search_factor_of_safety(settings, [](double F) { return fake_trial(F, 3.7); }, {});
  ASSERT_TRUE(fos.bracketed) << fos.message;
  EXPECT_LE(fos.lower, 3.7);
  EXPECT_GE(fos.upper, 3.7);
  EXPECT_DOUBLE_EQ(fos.trials[1].factor, 2.0);
  EXPECT_DOUBLE_EQ(fos.trials[2].factor, 3.0);
  EXPECT_DOUBLE_EQ(fos.trials[3].factor, 4.5);
}

TEST(StrengthReduction, StopsWhenTheRangeOrTheTrialsRunOut) {
  StrengthReductionSpec settings;
  const FactorOfSafety below =
      search_factor_of_safety(settings, [](double F) { return fake_trial(F, 0.8); }, {});
  EXPECT_FALSE(below.bracketed);
  EXPECT_EQ(below.trials.size(), 1u);
  EXPECT_NE(below.message.find("below the search range"), std::string::npos);

  settings.max_trials = 5;
  const FactorOfSafety above =
      search_factor_of_safety(settings, [](double F) { return fake_trial(F, 100.0); }, {});
  EXPECT_FALSE(above.bracketed);
  EXPECT_EQ(above.trials.size(), 5u);
  EXPECT_NE(above.message.find("above"), std::string::npos);

  settings.tolerance = 1e-6;
  const FactorOfSafety narrow =
      search_factor_of_safety(settings, [](double F) { return fake_trial(F, 1.5); }, {});
  EXPECT_FALSE(narrow.bracketed);
  EXPECT_EQ(narrow.trials.size(), 5u);
  EXPECT_NE(narrow.message.find("max_trials = 5 reached"), std::string::npos);
}

// The real search on the coarse slope: every trial ends with its reason logged, the files are
// written, and a second search does not overwrite the first without --force.
TEST(StrengthReduction, SearchWritesItsFilesAndKeepsEarlierResults) {
  const fs::path dir = fs::temp_directory_path() / ("talus_fos_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const CaseSpec spec = read_case_text(kSlope, "case.yaml");
  FosOptions options;
  options.out_dir = dir;
  options.threads = 1;
  const FosRunResult r = run_factor_of_safety(spec, options);
  ASSERT_TRUE(r.fos.bracketed) << r.fos.message;
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_GT(r.fos.value(), 1.0);
  EXPECT_LE(r.fos.upper - r.fos.lower, 0.5);
  for (const char* file : {"fos.csv", "fos.png", "fos.log", "fos.json"})
    EXPECT_TRUE(fs::exists(dir / file)) << file;
  std::ifstream log(dir / "fos.log");
  std::string line;
  int trial_lines = 0;
  while (std::getline(log, line))
    if (line.rfind("trial F = ", 0) == 0) {
      ++trial_lines;
      EXPECT_TRUE(line.find("stood:") != std::string::npos ||
                  line.find("failed") != std::string::npos)
          << line;
    }
  EXPECT_EQ(trial_lines, static_cast<int>(r.fos.trials.size()));
  const auto json = nlohmann::json::parse(std::ifstream(dir / "fos.json"));
  EXPECT_DOUBLE_EQ(json["factor_of_safety"].get<double>(), r.fos.value());
  // The trials ran in this process, so the search took processor time, and reports it.
  EXPECT_GT(r.cpu_seconds, 0.0);
  EXPECT_DOUBLE_EQ(json["cpu_seconds"].get<double>(), r.cpu_seconds);
  EXPECT_THROW(run_factor_of_safety(spec, options), InputError);
  options.force = true;
  EXPECT_EQ(run_factor_of_safety(spec, options).fos.trials.size(), r.fos.trials.size());
  fs::remove_all(dir);
}
