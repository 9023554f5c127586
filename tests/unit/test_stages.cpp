// Staged analyses (`stages:`): the state carries over from stage to stage, loads are not
// applied twice, a dynamic stage after a quasi-static one starts at rest, a stage's strength
// factor moves the stresses onto the weaker surface, and a stage ends at rest or on its
// wall-time limit with the reason recorded.
#include "talus/core/errors.hpp"
#include "talus/io/case_reader.hpp"
#include "talus/scene/scene.hpp"
#include "talus/solver/run.hpp"
#include "talus/solver/stage_watch.hpp"
#include "temporary_directory.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <string>
#include <vector>

namespace {

using namespace talus;

// A 1 m x 2 m column on a fixed base between rollers, loaded by its weight: one-dimensional
// (confined) compression, which stands for any strength. The settlement of the top is about
// rho g H^2 / (2 M) = 2000 * 10 * 4 / (2 * 1.35e7) = 3e-3 m.
const std::string kColumn = R"(name: column
grid: {origin: [0, 0], extent: [1, 2.5], cell_size: 0.25}
materials:
  - {name: soil, model: MATERIAL, density: 2000, youngs_modulus: 1.0e7, poisson_ratio: 0.3}
bodies:
  - {name: c, material: soil, shape: rectangle, min: [0, 0], max: [1, 2]}
gravity: [0, -10]
boundaries: {x_min: roller, x_max: roller, y_min: fixed}
output: {fields: [velocity, stress, plastic_strain, reference_position]}
stages:
  - {name: gravity, analysis: implicit_quasistatic, time: {end_time: 1, dt: 0.25}}
STAGE2)";

std::string column(const std::string& material, const std::string& second_stage) {
  std::string text = kColumn;
  text.replace(text.find("MATERIAL"), 8, material);
  text.replace(text.find("STAGE2"), 6, second_stage);
  return text;
}

const std::string kElastic = "linear_elastic";
const std::string kTresca = "tresca, cohesion: 2.0e4";

class StagedRuns : public talus::test_support::TemporaryDirectoryTest {
protected:
  /// Runs the case text and hands back the final state's positions and stresses.
  RunResult run(const std::string& text, const std::string& label) {
    const CaseSpec spec = read_case_text(text, label + ".yaml");
    RunOptions options;
    options.out_dir = root_ / label;
    options.progress = false;
    options.final_state = [this](const Scene<2>& scene) {
      x_.assign(scene.particles.x.begin(), scene.particles.x.end());
      x0_.assign(scene.particles.x0.begin(), scene.particles.x0.end());
      // Kirchhoff stress J sigma: the finite-strain return map works on it.
      kirchhoff_.clear();
      for (std::size_t p = 0; p < scene.particles.stress.size(); ++p)
        kirchhoff_.push_back(scene.particles.F[p].determinant() * scene.particles.stress[p]);
    };
    return run_case(spec, options);
  }
  nlohmann::json summary(const std::string& label) const {
    std::ifstream in(root_ / label / "summary.json");
    return nlohmann::json::parse(in);
  }
  std::vector<Vec2> x_, x0_;
  std::vector<Mat3> kirchhoff_;
};

std::string without_plastic_strain(std::string text) {
  const std::string field = ", plastic_strain";
  text.erase(text.find(field), field.size());
  return text;
}

// The gravity state is an equilibrium: a dynamic stage after it must not move the column. A
// load applied twice, or the quasi-static stage's pseudo-velocities (the last load step's
// settlement per pseudo-time step, ~3e-3 m/s) carried into the dynamics as real velocities,
// would set it vibrating (measured: 3e-3 of the settlement at the end with the velocities
// carried over). What may move it: each step re-samples the stress at the moved points (MPM
// quadrature), which leaves an imbalance of about 1e-3 of the load (newton.log: the first
// residual of the dynamic steps); the motion it drives is measured at 1e-5 of the settlement,
// and bounded here by 1e-4.
TEST_F(StagedRuns, TheGravityStateStaysPutInADynamicStage) {
  const std::string one_stage = without_plastic_strain(column(kElastic, ""));
  const std::string two_stages = without_plastic_strain(column(
      kElastic, "  - {name: hold, analysis: implicit_dynamic, time: {end_time: 0.2, dt: 0.02}}\n"));
  const RunResult a = run(one_stage, "one");
  ASSERT_EQ(a.status, "completed") << a.message;
  const std::vector<Vec2> gravity_state = x_;
  double settlement = 0;
  for (std::size_t p = 0; p < x_.size(); ++p)
    settlement = std::max(settlement, x0_[p].y() - x_[p].y());
  ASSERT_GT(settlement, 1e-3) << "the column did not settle under its weight";
  const RunResult b = run(two_stages, "two");
  ASSERT_EQ(b.status, "completed") << b.message;
  ASSERT_EQ(x_.size(), gravity_state.size());
  double moved = 0;
  for (std::size_t p = 0; p < x_.size(); ++p)
    moved = std::max(moved, (x_[p] - gravity_state[p]).norm());
  EXPECT_LT(moved, 1e-4 * settlement);
  EXPECT_DOUBLE_EQ(b.final_time, 1.2);

  const nlohmann::json s = summary("two");
  ASSERT_EQ(s["stages"].size(), 2u);
  EXPECT_EQ(s["stages"][0]["name"], "gravity");
  EXPECT_EQ(s["stages"][0]["end"], "end_time reached");
  EXPECT_EQ(s["stages"][1]["analysis"], "implicit_dynamic");
  EXPECT_DOUBLE_EQ(s["stages"][1]["start_time"].get<double>(), 1.0);
  EXPECT_EQ(s["stages"][0]["steps"], a.steps);
  EXPECT_EQ(s["stages"][1]["steps"], b.steps - a.steps);
  EXPECT_GE(b.steps - a.steps, 10) << "0.2 s in steps of at most 0.02 s";

  // timeseries.csv: a stage column, and the run's time continuing through the second stage.
  std::ifstream csv(root_ / "two" / "timeseries.csv");
  std::string header, line, last;
  std::getline(csv, header);
  EXPECT_NE(header.find(",stage"), std::string::npos) << header;
  while (std::getline(csv, line))
    if (!line.empty())
      last = line;
  EXPECT_EQ(last.substr(0, 3), "1.2") << last;
}

// A quasi-static stage with strength factor 4 takes a Tresca column from c = 20 kPa, where its
// gravity state is elastic (largest shear stress about 0.29 rho g H = 11.4 kPa), to c / 4 =
// 5 kPa: at the end no point's shear stress exceeds 5 kPa and the deep points sit on the
// surface (Kirchhoff stress, on which the finite-strain return map works: exact to
// round-off), and the confined column still stands.
TEST_F(StagedRuns, AStrengthFactorReturnsTheStressesToTheWeakerSurface) {
  const std::string text =
      column(kTresca, "  - {name: weaken, analysis: implicit_quasistatic, strength_factor: 4,\n"
                      "     time: {end_time: 1, dt: 0.25}}\n");
  const RunResult one = run(column(kTresca, ""), "gravity");
  ASSERT_EQ(one.status, "completed") << one.message;
  auto max_shear = [](const Mat3& s) {
    Eigen::SelfAdjointEigenSolver<Mat3> eig(s);
    return 0.5 * (eig.eigenvalues().maxCoeff() - eig.eigenvalues().minCoeff());
  };
  double before = 0;
  for (const Mat3& s : kirchhoff_)
    before = std::max(before, max_shear(s));
  EXPECT_GT(before, 1.5 * 5e3) << "the gravity state must lie outside the weakened surface";
  EXPECT_LT(before, 2e4) << "and inside the full-strength one";

  const RunResult r = run(text, "weakened");
  ASSERT_EQ(r.status, "completed") << r.message;
  double after = 0;
  for (const Mat3& s : kirchhoff_)
    after = std::max(after, max_shear(s));
  // The return map puts the stress on the surface to round-off (1e-10 of c).
  EXPECT_LE(after, 5e3 * (1 + 1e-9));
  EXPECT_GT(after, 5e3 * (1 - 1e-9)) << "the deepest points should be on the weakened surface";
  const nlohmann::json s = summary("weakened");
  EXPECT_DOUBLE_EQ(s["stages"][1]["strength_factor"].get<double>(), 4.0);
}

// A wall-time limit far below one step's cost stops the stage, and the run, after its first
// step: status interrupted (exit 1), the reason in summary.json, the later stage not run, and
// the frames written so far kept.
TEST_F(StagedRuns, AWallTimeLimitStopsTheRunAndSaysSo) {
  const std::string text = without_plastic_strain(
      column(kElastic,
             "  - {name: hold, analysis: implicit_dynamic, time: {end_time: 0.2, dt: 0.02},\n"
             "     wall_time_limit: 1.0e-9}\n"
             "  - {name: never, analysis: implicit_dynamic, time: {end_time: 0.2, dt: 0.02}}\n"));
  const RunResult r = run(text, "limited");
  EXPECT_EQ(r.status, "interrupted");
  EXPECT_EQ(r.exit_code, kExitOther);
  EXPECT_NE(r.message.find("wall-time limit"), std::string::npos) << r.message;
  const nlohmann::json s = summary("limited");
  ASSERT_EQ(s["stages"].size(), 2u) << "the third stage must not run";
  EXPECT_EQ(s["stages"][1]["steps"], 1);
  EXPECT_EQ(s["stages"][1]["end"].get<std::string>().rfind("wall-time limit", 0), 0u);
  EXPECT_GE(r.frames, 2);
}

// --- StageWatch: the at-rest criterion on a prescribed motion ----------------------------------

// One point of 2 kg moving at speeds[k] during step k (dt = 0.1 s), so its motion energy is
// speeds[k]^2, watched for rest with ratio 1e-2 and duration 0.5 s. Returns the stage time at
// which the watch ended the stage (-1 if it did not) and its reason.
std::pair<double, std::string> rest_time(const std::vector<double>& speeds) {
  StageSpec stage;
  stage.name = "slide";
  stage.analysis = AnalysisType::ImplicitDynamic;
  stage.at_rest = RestCriterion{1e-2, 0.5};
  StageWatch watch(stage);
  Particles<2> P;
  P.x = {Vec2(0, 0)};
  P.mass = {2.0};
  const double dt = 0.1;
  for (std::size_t k = 0; k < speeds.size(); ++k) {
    const double t = dt * static_cast<double>(k + 1);
    watch.before_step(P);
    P.x[0].x() += speeds[k] * dt;
    if (watch.ends_after_step(P, t, dt)) {
      EXPECT_FALSE(watch.out_of_time());
      return {t, watch.reason()};
    }
  }
  return {-1.0, ""};
}

TEST(StageWatch, EndsOnceTheMotionStaysQuietForTheDuration) {
  // Speeds 1, 3 (peak: energy 9), then 0.2 (energy 0.04 <= 0.09): quiet from t = 0.3 on.
  const auto [t, reason] = rest_time({1, 3, 0.2, 0.2, 0.2, 0.2, 0.2, 0.2});
  EXPECT_NEAR(t, 0.8, 1e-12) << "quiet from 0.3, held 0.5 s";
  EXPECT_EQ(reason.rfind("at rest", 0), 0u) << reason;
}

TEST(StageWatch, MotionAboveTheRatioRestartsTheQuietPeriod) {
  // Peak 9, quiet at 0.3 and 0.4, a lurch (speed 0.5, energy 0.25 > 0.09) at 0.5, quiet again
  // from 0.6: the stage ends at 0.6 + 0.5 = 1.1, not at 0.8.
  const auto [t, reason] = rest_time({1, 3, 0.2, 0.2, 0.5, 0.2, 0.2, 0.2, 0.2, 0.2, 0.2, 0.2});
  EXPECT_NEAR(t, 1.1, 1e-12) << reason;
}

// --- input errors ------------------------------------------------------------------------------

void expect_input_error(const std::string& text, int line, const std::string& part) {
  try {
    read_case_text(text, "case.yaml");
    ADD_FAILURE() << "expected an InputError containing '" << part << "'";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().line, line) << e.what();
    EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
  }
}

TEST(StagedCaseErrors, SayWhatAndWhere) {
  const std::string base = without_plastic_strain(column(kElastic, ""));
  // Line numbers: the first stage is on line 11, an appended one on line 12.
  expect_input_error("analysis: explicit\n" + base, 1, "each stage gives its own analysis");
  expect_input_error(base + "  - {name: gravity, analysis: implicit_dynamic, time: {end_time: 1, "
                            "dt: 0.1}}\n",
                     12, "duplicate stage name 'gravity'");
  expect_input_error(base + "  - {name: b, analysis: implicit_quasistatic, time: {end_time: 1, "
                            "dt: 0.1}, at_rest: {}}\n",
                     12, "a quasi-static stage has none");
  expect_input_error(base + "  - {name: b, analysis: implicit_dynamic, strength_factor: 2, time: "
                            "{end_time: 1, dt: 0.1}}\n",
                     12, "no tresca, mohr_coulomb or drucker_prager");
  expect_input_error(base + "  - {name: b, analysis: implicit_dynamic, time: {end_time: 1, cfl: "
                            "0.5}}\n",
                     12, "a CFL number applies to explicit analyses");
  expect_input_error(base + "  - {name: b, analysis: implicit_dynamic, time: {end_time: 1, dt: "
                            "0.1}, at_rest: {kinetic_energy_ratio: 2}}\n",
                     12, "open interval (0, 1)");
  expect_input_error("solver: {transfer: apic}\n" + base, 1,
                     "'apic' is implemented in the explicit analysis only");
  expect_input_error("solver: {f_bar: true}\n" + base +
                         "  - {name: b, analysis: explicit, time: {end_time: 1, cfl: 0.5}}\n",
                     1, "stage 'b' is explicit");
}

} // namespace
