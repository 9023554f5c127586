// Strength reduction (talus fos): the case section, the weakened materials, the bisection with a
// fake trial whose critical factor is known, and how a trial's run is classified (the run hook
// that stops a trial, and small searches end to end: test_stop_after_step.cpp).
#include "strength_reduction_test_support.hpp"

using namespace talus;
using namespace talus::strength_reduction_test;

namespace {

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

/// What run_case would return for a trial that ended at `time` (of `end_time`) with `status`:
/// 8 steps for the full load, 3 Newton iterations a step, one cut-back.
RunResult fake_run(double end_time, double time, const std::string& status,
                   const std::string& message, double stiffness = 0.8, bool stalled = false) {
  RunResult run;
  run.extra["current_stiffness"] = stiffness;
  if (stalled)
    run.extra["newton_stalled"] = 1.0;
  run.status = status;
  run.message = message;
  run.exit_code = status == "completed" ? 0 : status == "numerical_failure" ? 3 : 1;
  run.final_time = time;
  run.steps = static_cast<Index>(std::lround(time / end_time * 8));
  run.extra["newton_iterations"] = 3.0 * static_cast<double>(run.steps);
  run.extra["cutbacks"] = 1;
  run.wall_seconds = 0.5;
  return run;
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
  EXPECT_DOUBLE_EQ(spec.strength_reduction->min_stiffness, 0.1);
  EXPECT_FALSE(spec.strength_reduction->displacement_limit);
  EXPECT_DOUBLE_EQ(
      read_case_text(with(kSlope, "probe: crest}", "probe: crest, min_stiffness: 0.2}"),
                     "case.yaml")
          .strength_reduction->min_stiffness,
      0.2);
  const CaseSpec limited = read_case_text(
      with(kSlope, "probe: crest}", "probe: crest, displacement_limit: 0.5}"), "case.yaml");
  EXPECT_DOUBLE_EQ(*limited.strength_reduction->displacement_limit, 0.5);
  // The incremental mode's smallest step: a 64th of the tolerance unless given.
  EXPECT_DOUBLE_EQ(spec.strength_reduction->smallest_step(), 0.5 / 64);
  const CaseSpec stepped = read_case_text(
      with(kSlope, "probe: crest}", "probe: crest, mode: incremental, min_step: 0.001}"),
      "case.yaml");
  EXPECT_DOUBLE_EQ(stepped.strength_reduction->smallest_step(), 0.001);
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
  EXPECT_NE(error_of(with(kSlope, "probe: crest}", "probe: crest, min_stiffness: 1}"))
                .find("must be below 1"),
            std::string::npos);
  EXPECT_NE(error_of(with(kSlope, "probe: crest}", "probe: crest, min_stiffness: 0}"))
                .find("min_stiffness"),
            std::string::npos);
  EXPECT_NE(error_of(with(kSlope, "probe: crest}", "probe: crest, min_step: 0.01}"))
                .find("'min_step' is the incremental mode's"),
            std::string::npos);
  EXPECT_NE(error_of(with(kSlope, "probe: crest}", "probe: crest, mode: incremental, min_step: 1}"))
                .find("must be at most the tolerance (0.5)"),
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

// Davis's associated equivalent (flow_rule: davis) of the reduced strength: with psi = 0,
// beta = cos(phi_F), so tan(phi*) = sin(phi_F) and c* = c_F cos(phi_F) (Davis 1968); psi* =
// phi*; an associated material (psi = phi_F) is its own equivalent; the residual strength
// follows with the same psi.
TEST(StrengthReduction, DavisFlowRuleGivesTheAssociatedEquivalent) {
  const double degree = std::numbers::pi / 180.0;
  const double F = 1.5;
  const CaseSpec given =
      read_case_text(with(with(kSlope, "probe: crest}", "probe: crest, flow_rule: davis}"),
                          "dilation_angle: 5", "dilation_angle: 0"),
                     "case.yaml");
  ASSERT_EQ(given.strength_flow_rule, StrengthReductionFlow::Davis);
  const MaterialSpec soil = reduce_strength(given, F).materials[0];
  const double phi_F = std::atan(std::tan(20 * degree) / F);
  EXPECT_NEAR(std::tan(soil.friction_angle * degree), std::sin(phi_F), 1e-14);
  EXPECT_NEAR(soil.cohesion, 1.0e4 / F * std::cos(phi_F), 1e-9);
  const double phi_res_F = std::atan(std::tan(15 * degree) / F);
  EXPECT_NEAR(std::tan(soil.residual->friction_angle * degree), std::sin(phi_res_F), 1e-14);
  EXPECT_NEAR(soil.residual->cohesion, 5.0e3 / F * std::cos(phi_res_F), 1e-9);
  EXPECT_DOUBLE_EQ(soil.dilation_angle, soil.residual->friction_angle); // psi* <= phi* throughout

  MaterialSpec dilating = given.materials[0];
  dilating.residual.reset();
  dilating.dilation_angle = 20;
  const MaterialSpec associated = reduce_strength(dilating, F, StrengthReductionFlow::Davis);
  EXPECT_NEAR(associated.friction_angle, phi_F / degree, 1e-12);
  EXPECT_NEAR(associated.cohesion, 1.0e4 / F, 1e-9);
  // The default keeps the case's flow rule.
  EXPECT_EQ(read_case_text(kSlope, "case.yaml").strength_flow_rule, StrengthReductionFlow::AsGiven);
  EXPECT_NE(error_of(with(kSlope, "probe: crest}", "probe: crest, flow_rule: associated}"))
                .find("unknown value 'associated' (allowed: as_given, davis)"),
            std::string::npos);
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

// Each way a trial's run can end, as the search counts it.
TEST(StrengthReduction, ClassifiesATrialByHowItsRunEnded) {
  // A stiffness path that stays stiff, and one heading for a limit point at 80 % of the load.
  StiffnessPath stiff{{0.25, 0.5, 0.75}, {1.0, 0.95, 0.9}};
  StiffnessPath softening{{0.6, 0.75}, {0.9, 0.3}};
  const auto classify = [](const StrengthReductionSpec& s, double factor, const RunResult& run,
                           double end_time, double dx, double dy,
                           const StiffnessPath& path = StiffnessPath{}) {
    return classify_trial(s, factor, run, end_time, dx, dy, path, 1.0 / 32);
  };
  StrengthReductionSpec settings;
  settings.probe = "crest";
  // Completed with the crest inside the limit, or without a limit: stood.
  settings.displacement_limit = 0.5;
  StrengthTrial t = classify(settings, 1.3, fake_run(1, 1, "completed", ""), 1, 0.03, -0.04);
  EXPECT_FALSE(t.failed) << t.reason;
  EXPECT_EQ(t.end, TrialEnd::Stood);
  EXPECT_DOUBLE_EQ(t.factor, 1.3);
  EXPECT_DOUBLE_EQ(t.crest_displacement(), 0.05);
  EXPECT_DOUBLE_EQ(t.load_reached, 1.0);
  EXPECT_DOUBLE_EQ(t.current_stiffness, 0.8);
  EXPECT_EQ(t.load_steps, 8);
  EXPECT_EQ(t.newton_iterations, 24);
  EXPECT_EQ(t.cutbacks, 1);
  EXPECT_NE(t.reason.find("stood: full load in 8 steps"), std::string::npos) << t.reason;
  // Completed, but the crest beyond the limit (a run the limit did not stop): failed.
  t = classify(settings, 1.5, fake_run(1, 1, "completed", ""), 1, 0.6, -0.8);
  EXPECT_TRUE(t.failed);
  EXPECT_EQ(t.end, TrialEnd::Displacement);
  EXPECT_NE(t.reason.find("crest moved 1 m, beyond the displacement limit 0.5 m"),
            std::string::npos)
      << t.reason;
  settings.displacement_limit.reset();
  EXPECT_FALSE(classify(settings, 1.5, fake_run(1, 1, "completed", ""), 1, 0.6, -0.8).failed);
  // Stopped by the watch during the loading: by the stiffness (a mechanism) when the last
  // stiffness is below min_stiffness, else by the crest limit; the load is t / end_time.
  settings.displacement_limit = 0.5;
  t = classify(settings, 1.45,
               fake_run(2, 1.25, "stopped", "crest moved 0.61 m > limit 0.5 m at load 0.625"), 2,
               0.4, -0.46);
  EXPECT_TRUE(t.failed);
  EXPECT_EQ(t.end, TrialEnd::Displacement);
  EXPECT_DOUBLE_EQ(t.load_reached, 0.625);
  EXPECT_EQ(t.reason, "failed: crest moved 0.61 m > limit 0.5 m at load 0.625 (crest moved 0.6096 "
                      "m; 5 steps, 15 Newton iterations, 1 cut-backs)");
  t = classify(settings, 1.45,
               fake_run(1, 0.75, "stopped", "current stiffness 0.03 < min_stiffness 0.05", 0.03), 1,
               0.01, 0);
  EXPECT_TRUE(t.failed);
  EXPECT_EQ(t.end, TrialEnd::Stiffness);
  // Newton at min_dt while the slope is still stiff: undecided, counted as failed, and said so.
  t = classify(
      settings, 1.6,
      fake_run(1, 0.75, "numerical_failure", "Newton did not converge", 0.4, /*stalled=*/true), 1,
      0.1, 0, stiff);
  EXPECT_TRUE(t.failed);
  EXPECT_EQ(t.end, TrialEnd::NewtonBudget);
  EXPECT_NE(t.reason.find("undecided, counted as failed"), std::string::npos) << t.reason;
  EXPECT_NE(t.reason.find("current stiffness was 0.4, above min_stiffness 0.1"), std::string::npos)
      << t.reason;
  // ... but a mechanism when the stiffness, falling, reaches zero within the step Newton could
  // not take: from 0.3 at 75 % it extrapolates to zero at 82.5 %, and the step of 1/32 from 80 %
  // reaches 83.1 %; from 75 % it would end at 78.1 %, short of the limit point.
  RunResult stalled =
      fake_run(1, 0.8, "numerical_failure", "Newton did not converge", 0.3, /*stalled=*/true);
  t = classify(settings, 1.6, stalled, 1, 0.1, 0, softening);
  EXPECT_TRUE(t.failed);
  EXPECT_EQ(t.end, TrialEnd::LimitPoint);
  EXPECT_NE(t.reason.find("extrapolates to zero at 82.5 %"), std::string::npos) << t.reason;
  stalled.final_time = 0.75;
  EXPECT_EQ(classify(settings, 1.6, stalled, 1, 0.1, 0, softening).end, TrialEnd::NewtonBudget);
  // ... and a mechanism when the stiffness falls faster with each step and its line reaches zero
  // before the full load: from 0.7 at 70 % to 0.4 at 80 % (three times the slope of the step
  // before) it extrapolates to zero at 93.3 %, beyond the step Newton could not take (83.1 %).
  // Falling ever faster, the curve meets zero before its line does: the full load is out of
  // reach. The same last two steps after a steeper one are a decline that slows down: undecided.
  stalled.final_time = 0.8;
  t = classify(settings, 1.6, stalled, 1, 0.1, 0, StiffnessPath{{0.5, 0.7, 0.8}, {0.9, 0.7, 0.4}});
  EXPECT_EQ(t.end, TrialEnd::LimitPoint) << t.reason;
  EXPECT_NE(t.reason.find("falling faster with each step, extrapolates to zero at 93.33 %"),
            std::string::npos)
      << t.reason;
  EXPECT_EQ(
      classify(settings, 1.6, stalled, 1, 0.1, 0, StiffnessPath{{0.5, 0.7, 0.8}, {1.5, 0.7, 0.4}})
          .end,
      TrialEnd::NewtonBudget);
  // ... nor when the line's zero lies beyond the full load: 0.55 at 80 % after 0.7 at 70 %.
  EXPECT_EQ(
      classify(settings, 1.6, stalled, 1, 0.1, 0, StiffnessPath{{0.5, 0.7, 0.8}, {0.9, 0.7, 0.55}})
          .end,
      TrialEnd::NewtonBudget);
  stalled.final_time = 0.75;
  // ... and a mechanism when the slope has already lost most of its stiffness: below
  // kStallStiffness min_stiffness (0.2 with the default 0.1), whatever the trend.
  StiffnessPath soft{{0.5, 0.75}, {0.16, 0.15}};
  t = classify(settings, 1.6, stalled, 1, 0.1, 0, soft);
  EXPECT_EQ(t.end, TrialEnd::LimitPoint);
  EXPECT_NE(t.reason.find("the current stiffness 0.15 was below 2 min_stiffness"),
            std::string::npos)
      << t.reason;
  // Another numerical stop (max_steps, the state guard): failed at the load reached.
  t = classify(settings, 1.6, fake_run(1, 0.75, "numerical_failure", "reached max_steps"), 1, 0.1,
               0);
  EXPECT_TRUE(t.failed);
  EXPECT_EQ(t.end, TrialEnd::Numerical);
  EXPECT_EQ(t.reason, "failed at 75.0 % of the load (crest moved 0.1 m): reached max_steps");
  // Interrupted: failed, and said so (the search then stops).
  t = classify(settings, 1.6, fake_run(1, 0.5, "interrupted", "interrupted"), 1, 0, 0);
  EXPECT_TRUE(t.failed);
  EXPECT_EQ(t.end, TrialEnd::Interrupted);
  EXPECT_EQ(t.reason, "interrupted");
}

// The limit point a loading heads for: the stiffness's straight line through the last two steps
// meets zero; none while it does not fall or with fewer than two steps.
TEST(StrengthReduction, ExtrapolatesTheStiffnessToItsLimitPoint) {
  EXPECT_NEAR((StiffnessPath{{0.6, 0.75}, {0.8, 0.2}}.extrapolated_limit()), 0.8, 1e-15);
  EXPECT_NEAR((StiffnessPath{{0.25, 1.3, 1.35}, {1, 0.5, 0.25}}.extrapolated_limit()), 1.4, 1e-14);
  EXPECT_TRUE(std::isinf(StiffnessPath{{0.5, 0.75}, {0.8, 0.8}}.extrapolated_limit()));
  EXPECT_TRUE(std::isinf(StiffnessPath{{0.5, 0.75}, {0.5, 0.8}}.extrapolated_limit()));
  EXPECT_TRUE(std::isinf(StiffnessPath{{0.5}, {0.1}}.extrapolated_limit()));
  // Falling faster: the last step's slope at least as steep as the one before, both falling.
  EXPECT_TRUE((StiffnessPath{{1.0, 1.1, 1.15}, {0.9, 0.8, 0.7}}.falling_faster()));
  EXPECT_TRUE(
      (StiffnessPath{{1.0, 1.1, 1.2}, {0.9, 0.8, 0.7}}.falling_faster())); // a straight line
  EXPECT_FALSE((StiffnessPath{{1.0, 1.1, 1.3}, {0.9, 0.8, 0.7}}.falling_faster()));
  EXPECT_FALSE((StiffnessPath{{1.0, 1.1, 1.2}, {0.8, 0.8, 0.7}}.falling_faster())); // flat first
  EXPECT_FALSE((StiffnessPath{{1.1, 1.2}, {0.8, 0.1}}.falling_faster()));           // two steps
}

// In the incremental run the reach is the search tolerance above the last factor that stood,
// and the bracket's failing end the line's zero when it lies beyond the failed step.
TEST(StrengthReduction, StallMechanismBoundsTheLimitPoint) {
  StrengthReductionSpec settings;
  const StiffnessPath path{{1.59, 1.60, 1.604}, {0.9, 0.8, 0.7}}; // slopes -10, -25
  // zero at 1.604 + 0.7 / 25 = 1.632: within a tolerance of 0.04 above 1.604, not of 0.02.
  const auto m = stall_mechanism(settings, path, 1.605, 1.604 + 0.04, 1.0, "");
  ASSERT_TRUE(m);
  EXPECT_NEAR(m->limit_by, 1.632, 1e-12);
  EXPECT_FALSE(stall_mechanism(settings, path, 1.605, 1.604 + 0.02, 1.0, ""));
  // Within the failed step, the step's end bounds it.
  const auto within = stall_mechanism(settings, path, 1.64, 1.604 + 0.02, 1.0, "");
  ASSERT_TRUE(within);
  EXPECT_DOUBLE_EQ(within->limit_by, 1.64);
}

// The hook ends an implicit run after the step it objects to: status "stopped" with its
// message, that step's row and frame written, the earlier frames intact.
