// The failure criterion of a strength-reduction trial (strength_reduction.hpp): the current
// stiffness after each converged load step, a stall judged by where the stiffness heads, and
// how a finished run is classified (docs/case-format.md#strength_reduction).
#include "talus/solver/strength_reduction.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <limits>

namespace talus {

double StrengthTrial::crest_displacement() const {
  return std::hypot(crest_dx, crest_dy);
}

const char* to_string(TrialEnd end) {
  switch (end) {
  case TrialEnd::Stood:
    return "stood";
  case TrialEnd::Stiffness:
    return "stiffness";
  case TrialEnd::LimitPoint:
    return "limit_point";
  case TrialEnd::Displacement:
    return "displacement";
  case TrialEnd::NewtonBudget:
    return "newton_budget";
  case TrialEnd::Numerical:
    return "numerical";
  case TrialEnd::InitialStress:
    return "initial_stress";
  case TrialEnd::Interrupted:
    return "interrupted";
  }
  return "?";
}

std::optional<StallMechanism> stall_mechanism(const StrengthReductionSpec& settings,
                                              const StiffnessPath& path, double failed_at,
                                              double reach, double scale, const char* unit) {
  if (path.stiffness.empty())
    return std::nullopt;
  const double stiffness = path.stiffness.back();
  if (stiffness < kStallStiffness * settings.min_stiffness)
    return StallMechanism{fmt::format("the current stiffness {:.3g} was below {:g} min_stiffness",
                                      stiffness, kStallStiffness),
                          failed_at};
  const double limit = path.extrapolated_limit();
  if (limit <= failed_at)
    return StallMechanism{fmt::format("the current stiffness {:.3g} extrapolates to zero at "
                                      "{:.4g}{}, within the step it could not take",
                                      stiffness, scale * limit, unit),
                          failed_at};
  if (limit <= reach && path.falling_faster())
    return StallMechanism{fmt::format("the current stiffness {:.3g}, falling faster with each "
                                      "step, extrapolates to zero at {:.4g}{}",
                                      stiffness, scale * limit, unit),
                          limit};
  return std::nullopt;
}

double StiffnessPath::extrapolated_limit() const {
  const std::size_t n = stiffness.size();
  if (n < 2)
    return std::numeric_limits<double>::infinity();
  const double slope = (stiffness[n - 1] - stiffness[n - 2]) / (control[n - 1] - control[n - 2]);
  if (!(slope < 0))
    return std::numeric_limits<double>::infinity();
  return control[n - 1] - stiffness[n - 1] / slope;
}

bool StiffnessPath::falling_faster() const {
  const std::size_t n = stiffness.size();
  if (n < 3)
    return false;
  const double last = (stiffness[n - 1] - stiffness[n - 2]) / (control[n - 1] - control[n - 2]);
  const double before = (stiffness[n - 2] - stiffness[n - 3]) / (control[n - 2] - control[n - 3]);
  return before < 0 && last <= before;
}

std::function<std::optional<std::string>(const StepState&)>
failure_watch(const StrengthReductionSpec& settings, std::function<std::string(double)> where) {
  return [&settings, where = std::move(where)](const StepState& s) -> std::optional<std::string> {
    if (s.current_stiffness < settings.min_stiffness)
      return fmt::format("current stiffness {:.3g} < min_stiffness {:g} {}: a mechanism",
                         s.current_stiffness, settings.min_stiffness, where(s.time));
    if (!settings.displacement_limit)
      return std::nullopt;
    const auto crest = std::find_if(s.probes.begin(), s.probes.end(),
                                    [&](const ProbeState& p) { return p.name == settings.probe; });
    const double moved = (crest->current - crest->initial).norm();
    if (moved <= *settings.displacement_limit)
      return std::nullopt;
    return fmt::format("crest moved {:.4g} m > limit {:g} m {}", moved,
                       *settings.displacement_limit, where(s.time));
  };
}

StrengthTrial classify_trial(const StrengthReductionSpec& settings, double factor,
                             const RunResult& run, double end_time, double crest_dx,
                             double crest_dy, const StiffnessPath& path, double min_step) {
  StrengthTrial trial;
  trial.factor = factor;
  trial.seconds = run.wall_seconds;
  trial.load_reached = run.final_time / end_time;
  trial.load_steps = run.steps;
  auto stat = [&](const char* key) {
    const auto it = run.extra.find(key);
    return it == run.extra.end() ? Index{0} : static_cast<Index>(it->second);
  };
  trial.newton_iterations = stat("newton_iterations");
  trial.cutbacks = stat("cutbacks");
  if (const auto it = run.extra.find("current_stiffness"); it != run.extra.end())
    trial.current_stiffness = it->second;
  trial.crest_dx = crest_dx;
  trial.crest_dy = crest_dy;
  const double moved = trial.crest_displacement();
  const std::string effort = fmt::format("{} steps, {} Newton iterations, {} cut-backs", run.steps,
                                         trial.newton_iterations, trial.cutbacks);
  trial.failed = true;
  if (run.status == "interrupted") {
    trial.end = TrialEnd::Interrupted;
    trial.reason = "interrupted";
  } else if (run.status == "stopped") { // by failure_watch, after a converged step
    trial.end = trial.current_stiffness < settings.min_stiffness ? TrialEnd::Stiffness
                                                                 : TrialEnd::Displacement;
    trial.reason = fmt::format("failed: {} (crest moved {:.4g} m; {})", run.message, moved, effort);
  } else if (const auto mechanism =
                 stat("newton_stalled") > 0
                     ? stall_mechanism(settings, path, trial.load_reached + min_step, 1.0, 100.0,
                                       " %")
                     : std::nullopt) {
    trial.end = TrialEnd::LimitPoint;
    trial.reason = fmt::format("failed: Newton did not converge beyond {:.1f} % of the load, "
                               "where {}: a mechanism (crest moved {:.4g} m; {})",
                               100.0 * trial.load_reached, mechanism->why, moved, effort);
  } else if (run.exit_code != 0 && stat("newton_stalled") > 0) {
    trial.end = TrialEnd::NewtonBudget;
    trial.reason = fmt::format(
        "undecided, counted as failed: Newton did not converge at the smallest load step at "
        "{:.1f} % of the load while the current stiffness was {:.3g}, above min_stiffness {:g} "
        "(no mechanism yet; crest moved {:.4g} m): raise solver.max_newton_iterations or lower "
        "time.min_dt ({})",
        100.0 * trial.load_reached, trial.current_stiffness, settings.min_stiffness, moved,
        run.message);
  } else if (run.exit_code != 0) {
    trial.end = TrialEnd::Numerical;
    trial.reason = fmt::format("failed at {:.1f} % of the load (crest moved {:.4g} m): {}",
                               100.0 * trial.load_reached, moved, run.message);
  } else if (settings.displacement_limit && moved > *settings.displacement_limit) {
    // A run without the stop: the crest limit judged on the final state.
    trial.end = TrialEnd::Displacement;
    trial.reason = fmt::format("failed: converged, but the crest moved {:.4g} m, beyond the "
                               "displacement limit {:g} m",
                               moved, *settings.displacement_limit);
  } else {
    trial.failed = false;
    trial.end = TrialEnd::Stood;
    trial.reason = fmt::format("stood: full load in {}; current stiffness {:.3g}, crest moved "
                               "{:.4g} m",
                               effort, trial.current_stiffness, moved);
  }
  return trial;
}

} // namespace talus
