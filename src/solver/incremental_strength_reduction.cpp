// Strength reduction in one run (strength_reduction.mode: incremental). The case is loaded at
// F = lower, as a trial would be; then quasi-static stages move F linearly, from lower to upper
// and on by half while the slope stands, each point keeping its stress and plastic history. The
// first step after which the current stiffness is below min_stiffness (or the crest beyond its
// limit) ends the run: the factor of safety lies between the factor of the last standing step
// and that one's. The nominal step moves F by at most `tolerance`, so that bracket is within
// the tolerance by construction. A step Newton cannot converge (at a quarter of the nominal
// step) also ends it, as undecided, while the slope is still stiff.
//
// Why: independent trials load the slope from scratch for every factor, and those that fail
// spend most of the search's time descending their cut-back ladders (Griffiths & Lane's slope:
// 85 % of 15 s). One loading and one failure cost about one failing trial. The answer is that of
// a different loading path, which a non-associated material may remember: docs/case-format.md
// gives both modes' answers and costs on the same slope.
#include "talus/solver/strength_reduction.hpp"

#include "talus/core/errors.hpp"
#include "talus/io/csv.hpp"
#include "talus/solver/run.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>

namespace talus {

namespace fs = std::filesystem;

namespace {

/// The factor F along the run's time: the loading stage holds `lower`; ramp j (from 1) spans
/// [load_end + j - 1, load_end + j] and moves F from factors[j - 1] to factors[j].
struct FactorPath {
  std::size_t history_stages = 0; ///< the loading's stages (one unless the case is staged)
  double load_end = 0;
  std::vector<double> factors; ///< factors[0] = lower, then each ramp's end
  std::vector<double> min_dt;  ///< per ramp (index j - 1)

  double at(double time) const {
    if (time <= load_end)
      return factors.front();
    const double s = time - load_end;
    const auto ramps = static_cast<double>(factors.size() - 1);
    const double j = std::min(std::floor(s), ramps - 1); // ramp j + 1, 0-based j
    const auto k = static_cast<std::size_t>(j);
    return factors[k] + (factors[k + 1] - factors[k]) * std::min(s - j, 1.0);
  }
  /// The smallest step of the ramp that a step starting at `time` belongs to.
  double min_step_after(double time) const {
    const double s = std::max(time - load_end, 0.0);
    const auto j = std::min(static_cast<std::size_t>(std::floor(s + 1e-12)), min_dt.size() - 1);
    return min_dt[j];
  }
};

/// The staged case: the loading at F = lower (a staged case's stages, its history), then ramps
/// to upper, 1.5 upper, ... (as many as the trials search would try), each in steps moving F
/// by at most `tolerance`. In consolidation the ramps are undrained: the water does not flow
/// during a pseudo-time, it carries the volume change of a failure faster than it drains.
CaseSpec staged_case(const CaseSpec& spec, FactorPath& path) {
  const StrengthReductionSpec& settings = *spec.strength_reduction;
  CaseSpec staged = spec;
  staged.strength_reduction.reset();
  if (spec.stages.empty()) {
    StageSpec load;
    load.name = "load";
    load.analysis = AnalysisType::ImplicitQuasistatic;
    load.time = spec.time;
    staged.stages.push_back(load);
  }
  staged.stages.front().strength_factor = settings.lower;
  path.history_stages = staged.stages.size();
  for (const StageSpec& stage : staged.stages)
    path.load_end += stage.time.end_time;
  path.factors = {settings.lower};
  double factor = settings.upper;
  for (int j = 1; j < settings.max_trials; ++j, factor *= 1.5) {
    const double span = factor - path.factors.back();
    StageSpec ramp;
    ramp.name = fmt::format("reduce_{}", j);
    ramp.analysis = AnalysisType::ImplicitQuasistatic;
    ramp.strength_factor = factor;
    // A power of two so that the steps land on the stage's end. Cut-backs go down to
    // min_step: near the limit the F step that Newton can take from the last converged state
    // shrinks with the cell size (the same slip is a larger strain in a thinner band), and a
    // stall at a coarser step is no evidence of a mechanism.
    const double dt = std::exp2(-std::ceil(std::log2(span / settings.tolerance)));
    ramp.time.end_time = 1.0;
    ramp.time.dt = std::min(dt, 1.0);
    ramp.time.min_dt = std::min(*ramp.time.dt, settings.smallest_step() / span);
    ramp.time.max_steps = static_cast<Index>(8.0 / *ramp.time.min_dt);
    ramp.undrained = spec.consolidates();
    staged.stages.push_back(ramp);
    path.factors.push_back(factor);
    path.min_dt.push_back(*ramp.time.min_dt);
  }
  return staged;
}

} // namespace

FactorOfSafety incremental_factor_of_safety(const CaseSpec& spec, const fs::path& dir,
                                            const FosOptions& search, bool& interrupted) {
  const StrengthReductionSpec& settings = *spec.strength_reduction;
  FactorPath path;
  const CaseSpec staged = staged_case(spec, path);
  RunOptions options;
  options.out_dir = dir;
  options.threads = search.threads;
  options.progress = true; // one long run: the user sees it advance
  options.measure_stiffness = true;
  // After a history or a consolidation the reduction's own first step is the reference: the
  // loading's u-p tangent (drained or not by its time step) is another stiffness.
  if (!spec.stages.empty() || spec.consolidates())
    options.measure_stiffness_from_stage = path.history_stages;
  options.stop_after_step = failure_watch(
      settings, [&path](double time) { return fmt::format("at F = {:.6g}", path.at(time)); });
  FactorOfSafety fos;
  StrengthTrial last;
  RunResult run;
  try {
    run = run_or_resume_trial(staged, options, search);
  } catch (const InputError& e) { // the reduced strength refused the initial stress
    last.factor = settings.lower;
    last.failed = true;
    last.end = TrialEnd::InitialStress;
    last.reason = fmt::format("failed before the first step: {}", e.what());
    fos.trials.push_back(last);
    fos.upper = settings.lower;
    fos.message = "the lowest factor fails before the first step";
    return fos;
  }
  interrupted = run.status == "interrupted";
  // One row per converged step of the ramps: the factor and where the crest stood.
  const CsvTable series = read_csv(dir / "timeseries.csv");
  const auto& time = series.column("time");
  const auto& x = series.column(settings.probe + ".x");
  const auto& y = series.column(settings.probe + ".y");
  const auto& stiffness = series.column("current_stiffness");
  StiffnessPath stiffness_path; // against F, from the end of the loading
  for (std::size_t r = 0; r < series.rows(); ++r) {
    if (time[r] < path.load_end * (1.0 - 1e-12) && r + 1 < series.rows())
      continue; // the loading's intermediate steps
    StrengthTrial step;
    step.factor = path.at(time[r]);
    step.load_reached = 1.0;
    step.load_steps = 1;
    step.crest_dx = x[r] - x.front();
    step.crest_dy = y[r] - y.front();
    step.current_stiffness = stiffness[r];
    step.reason = fmt::format("stood: current stiffness {:.3g}, crest moved {:.4g} m",
                              step.current_stiffness, step.crest_displacement());
    fos.trials.push_back(step);
    if (std::isfinite(step.current_stiffness)) { // not measured in a history
      stiffness_path.control.push_back(step.factor);
      stiffness_path.stiffness.push_back(step.current_stiffness);
    }
  }
  const auto stat = [&](const char* key) {
    const auto it = run.extra.find(key);
    return it == run.extra.end() ? Index{0} : static_cast<Index>(it->second);
  };
  const bool loaded = run.final_time >= path.load_end * (1.0 - 1e-12);
  StrengthTrial& end = fos.trials.back();
  end.newton_iterations = stat("newton_iterations");
  end.cutbacks = stat("cutbacks");
  end.seconds = run.wall_seconds;
  end.load_steps = run.steps;
  if (run.status == "completed") {
    fos.lower = end.factor;
    fos.message = fmt::format("stood up to F = {:g}: the factor of safety is above the path; "
                              "raise strength_reduction.upper",
                              end.factor);
    return fos;
  }
  if (interrupted) {
    end.end = TrialEnd::Interrupted;
    end.reason = "interrupted";
    fos.message = "interrupted";
    return fos;
  }
  if (!loaded) {
    end.failed = true;
    end.end = stat("newton_stalled") > 0 ? TrialEnd::NewtonBudget : TrialEnd::Numerical;
    end.load_reached = run.final_time / path.load_end;
    end.reason =
        fmt::format("failed during the loading at F = {:g}: {}", settings.lower, run.message);
    fos.upper = settings.lower;
    fos.message = fmt::format("the lowest factor F = {:g} already fails: the factor of safety is "
                              "below the search range; lower strength_reduction.lower",
                              settings.lower);
    return fos;
  }
  if (run.status == "stopped") { // failure_watch after the last converged step
    end.failed = true;
    end.end = end.current_stiffness < settings.min_stiffness ? TrialEnd::Stiffness
                                                             : TrialEnd::Displacement;
    end.reason = "failed: " + run.message;
    fos.upper = end.factor;
    fos.lower = fos.trials.size() > 1 ? fos.trials[fos.trials.size() - 2].factor : settings.lower;
  } else { // Newton at the smallest step (or another numerical stop) after the last row
    StrengthTrial failed = end;
    end.newton_iterations = end.cutbacks = 0;
    end.seconds = 0;
    end.load_steps = 1;
    failed.failed = true;
    failed.factor = path.at(run.final_time + path.min_step_after(run.final_time));
    const auto mechanism = stat("newton_stalled") > 0
                               ? stall_mechanism(settings, stiffness_path, failed.factor,
                                                 end.factor + settings.tolerance, 1.0, "")
                               : std::nullopt;
    fos.upper = mechanism ? mechanism->limit_by : failed.factor;
    if (mechanism) {
      failed.end = TrialEnd::LimitPoint;
      failed.reason =
          fmt::format("failed: Newton did not converge beyond F = {:.6g}, where {}: a mechanism",
                      end.factor, mechanism->why);
    } else if (stat("newton_stalled") > 0) {
      failed.end = TrialEnd::NewtonBudget;
      failed.reason = fmt::format(
          "undecided, counted as failed: Newton did not converge at the smallest step with the "
          "current stiffness {:.3g} above min_stiffness {:g} (no mechanism yet): {}",
          end.current_stiffness, settings.min_stiffness, run.message);
    } else {
      failed.end = TrialEnd::Numerical;
      failed.reason = "failed: " + run.message;
    }
    fos.lower = end.factor;
    fos.trials.push_back(failed);
  }
  fos.bracketed = fos.upper - fos.lower <= settings.tolerance * (1.0 + 1e-9);
  fos.message = fmt::format(
      "bracket [{:.4g}, {:.4g}]{} in one incremental run ({} steps)", fos.lower, fos.upper,
      fos.bracketed ? fmt::format(" within the tolerance {:g}", settings.tolerance)
                    : fmt::format(", wider than the tolerance {:g}", settings.tolerance),
      run.steps);
  return fos;
}

} // namespace talus
