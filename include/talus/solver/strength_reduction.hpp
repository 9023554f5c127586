#pragma once
// Factor of safety by strength reduction (Griffiths & Lane, Geotechnique 49 (1999) 387): the
// case is loaded quasi-statically, from scratch, with every frictional material's strength
// divided by a trial factor F (c / F, tan(phi) / F); the factor of safety is the smallest F at
// which the loading fails. A trial fails when a mechanism forms: the slope's current stiffness
// under its own weight (Bergan's parameter, measured with the consistent tangent after every
// converged load step) falls below `min_stiffness` of its first load step's. That is a
// property of the converged states, not of Newton's budget: a step Newton cannot converge
// while the slope is still stiff is reported as undecided (and counted as failed), never as a
// mechanism. A case may add a crest displacement limit. The search brackets the critical
// factor and bisects (docs/case-format.md#strength_reduction).
#include "talus/solver/run.hpp"
#include "talus/spec/case_spec.hpp"

#include <filesystem>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace talus {

/// The case with every tresca, mohr_coulomb and drucker_prager material weakened by `factor`
/// (with the case's strength_flow_rule):
/// c / F, phi_F = atan(tan(phi) / F), the residual strength likewise; the dilation angle, a
/// flow parameter and not a strength, is kept unless it exceeds the reduced (peak or residual)
/// phi, where it is capped (the models require psi <= phi). With StrengthReductionFlow::Davis
/// a non-associated material then becomes Davis's associated one: c* = beta c_F,
/// tan(phi*) = beta tan(phi_F), psi* = phi*, beta = cos(psi) cos(phi_F) / (1 - sin(psi)
/// sin(phi_F)), its residual strength likewise.
CaseSpec reduce_strength(const CaseSpec& spec, double factor);
/// One material weakened the same way (unchanged unless tresca, mohr_coulomb, drucker_prager).
MaterialSpec reduce_strength(const MaterialSpec& material, double factor,
                             StrengthReductionFlow flow);

/// What ended a trial (fos.csv's `criterion`).
enum class TrialEnd {
  Stood,         ///< the full load, stiffer than min_stiffness, the crest within its limit
  Stiffness,     ///< the current stiffness fell below min_stiffness: a mechanism
  LimitPoint,    ///< Newton failed at the smallest step, across the extrapolated limit point
  Displacement,  ///< the crest moved beyond displacement_limit
  NewtonBudget,  ///< Newton failed at the smallest step short of the limit point: undecided
  Numerical,     ///< another numerical stop (max_steps, the state guard)
  InitialStress, ///< the reduced strength refused the initial stress
  Interrupted,
};
/// "stood", "stiffness", "limit_point", "displacement", "newton_budget", "numerical",
/// "initial_stress", "interrupted".
const char* to_string(TrialEnd end);

/// The current stiffness after each converged step of a loading, against its control: the
/// load fraction of a trial, or F in the incremental run.
struct StiffnessPath {
  std::vector<double> control, stiffness;
  /// Where the stiffness, extended as a straight line through the last two steps, reaches
  /// zero: the limit point the loading was heading for; +infinity while it is not falling.
  double extrapolated_limit() const;
  /// Whether the stiffness fell over each of the last two steps, over the last at least as
  /// steeply as over the one before. Near a limit point the stiffness falls ever faster (as
  /// sqrt(limit - control) at a smooth one), so the straight line of extrapolated_limit() runs
  /// above the curve and the limit point comes before the line's zero.
  bool falling_faster() const;
};

/// What the loading at one trial factor found.
struct StrengthTrial {
  double factor = 0;
  bool failed = false; ///< a mechanism, or counted as one (TrialEnd other than Stood)
  TrialEnd end = TrialEnd::Stood;
  std::string reason; ///< why the trial ended (the log line)
  /// Bergan's current stiffness at the last converged step (NaN if none was measured).
  double current_stiffness = std::numeric_limits<double>::quiet_NaN();
  double load_reached = 0;           ///< t / end_time of the last converged step
  double crest_dx = 0, crest_dy = 0; ///< m, crest probe displacement at the last converged step
  Index load_steps = 0, newton_iterations = 0, cutbacks = 0;
  double seconds = 0; ///< wall time of the trial
  double crest_displacement() const;
};

/// A stall on a slope whose current stiffness is below this many min_stiffness is a mechanism:
/// near a limit point the tangent of the converged state overstates the stiffness (points that
/// unloaded elastically in the last step are stiff in it) while Newton can no longer follow.
constexpr double kStallStiffness = 2.0;

/// A mechanism met by Newton's failure at the smallest step: why, and the control by which
/// the limit point lies (the end of the step Newton could not take, or the stiffness's
/// extrapolated zero when that comes later).
struct StallMechanism {
  std::string why;
  double limit_by = 0;
};

/// Whether Newton's failure at the smallest step, after the converged steps of `path`, met a
/// mechanism, and which: the last stiffness below kStallStiffness min_stiffness; or its trend
/// reaching zero by `failed_at`, the control at the end of the step Newton could not take; or,
/// falling ever faster (StiffnessPath::falling_faster), reaching zero by `reach`, the control
/// that still decides the question (the full load of a trial; in the incremental run the
/// search tolerance above the last factor that stood). The description names the control
/// times `scale`, with `unit` ("%", or "" for F).
std::optional<StallMechanism> stall_mechanism(const StrengthReductionSpec& settings,
                                              const StiffnessPath& path, double failed_at,
                                              double reach, double scale, const char* unit);

/// What a trial's run says about the trial factor: it stood (the full load, the crest within
/// `displacement_limit`) or failed, and why (TrialEnd): stopped during the loading by the
/// stiffness criterion or the crest limit (status "stopped"); Newton at the smallest step
/// (summary "newton_stalled"), which is a mechanism by stall_mechanism() (the step it could not
/// take is `min_step` of the load long) and undecided otherwise; another numerical stop;
/// interrupted; or converged with the crest beyond the limit. `crest_dx`, `crest_dy`: the probe's
/// displacement at the run's last converged step; `path`: the stiffness after each converged step
/// against the load fraction.
StrengthTrial classify_trial(const StrengthReductionSpec& settings, double factor,
                             const RunResult& run, double end_time, double crest_dx,
                             double crest_dy, const StiffnessPath& path, double min_step);

/// The run hook of a trial or the incremental run (RunOptions::stop_after_step): after each
/// converged step, the current stiffness below settings.min_stiffness, or the crest beyond
/// settings.displacement_limit, ends the run with a message that names the step by
/// `where(time)` ("at load 0.75", "at F = 1.4"). Keeps a reference to `settings`.
std::function<std::optional<std::string>(const StepState&)>
failure_watch(const StrengthReductionSpec& settings, std::function<std::string(double)> where);

/// The outcome of the search.
struct FactorOfSafety {
  bool bracketed = false;            ///< a standing and a failing factor at most `tolerance` apart
  double lower = 0;                  ///< the largest factor that stood
  double upper = 0;                  ///< the smallest factor that failed
  std::string message;               ///< why the search ended
  std::vector<StrengthTrial> trials; ///< in the order they ran
  /// The smallest failed factor is a trial Newton could not decide (TrialEnd::NewtonBudget):
  /// the factor of safety may lie above the bracket.
  bool upper_undecided = false;
  /// The bracket's midpoint, the reported factor of safety.
  double value() const { return 0.5 * (lower + upper); }
};

/// The search, independent of how a trial runs: `lower` must stand (else the factor of safety
/// is below the range and the search stops), unless `floor` lies below it: then failing
/// factors step down towards `floor` (by the range's width, doubling) until one stands.
/// `upper` is raised by half while it stands; then the bracket is bisected until it is at most
/// `tolerance` wide. At most `max_trials` trials, so the search always ends. `on_trial` (may be
/// empty) sees each trial as it finishes.
FactorOfSafety search_factor_of_safety(const StrengthReductionSpec& settings,
                                       const std::function<StrengthTrial(double)>& trial,
                                       const std::function<void(const StrengthTrial&)>& on_trial,
                                       double floor = std::numeric_limits<double>::infinity());

/// The incremental search (strength_reduction.mode: incremental,
/// src/solver/incremental_strength_reduction.cpp): one run into `dir` that loads the case at
/// F = lower and then lowers the strength step by step from the loaded state. Its "trials" are
/// the run's steps (the factor each reached and the crest there), the last one the failure;
/// the run's Newton iterations, cut-backs and time are on the last row.
struct FosOptions {
  std::filesystem::path out_dir; ///< empty: results/<case name>-fos
  bool force = false;            ///< replace the files of an earlier search in out_dir
  int threads = 0;               ///< OpenMP threads of each trial; 0 keeps the default
  /// Continue the search in out_dir (which must be given): finished trials are kept, the one
  /// that was cut short continues from its newest checkpoint (or starts again without one).
  bool resume = false;
  bool accept_changes = false; ///< with resume: as RunOptions::accept_changes
  /// When `lower` fails, the search may step down to this factor (search_factor_of_safety;
  /// the incremental run starts its loading lower); infinity: `lower` must stand.
  double floor = std::numeric_limits<double>::infinity();
};

FactorOfSafety incremental_factor_of_safety(const CaseSpec& spec, const std::filesystem::path& dir,
                                            const FosOptions& search, bool& interrupted);

/// A trial's run into options.out_dir. Resuming a search (search.resume), a run that finished
/// there is taken from its summary.json as it is, one that was cut short continues from its
/// newest checkpoint, and one without a checkpoint starts again.
RunResult run_or_resume_trial(const CaseSpec& spec, RunOptions options, const FosOptions& search);

/// A staged case's search after one stage of its history (strength_reduction.after): the
/// strength reduced from the state the stage left (undrained in consolidation).
struct StageFactorOfSafety {
  std::string stage;
  double time = 0; ///< s, the history's time at the stage's end
  FactorOfSafety fos;
};

struct FosRunResult {
  /// The search; of a staged case, the one after the last stage searched.
  FactorOfSafety fos;
  std::vector<StageFactorOfSafety> history; ///< a staged case: each stage's search, in order
  std::filesystem::path out_dir;
  double wall_seconds = 0;
  /// Processor time of the search (user + system, all threads): on a machine shared with other
  /// work the wall time says little, this is the search's own cost.
  double cpu_seconds = 0;
  Index newton_iterations = 0; ///< summed over the trials
  int exit_code = 0;           ///< 0 bracketed, 3 not bracketed, 1 interrupted
};

/// The incremental search of a consolidation case lowers the strength undrained: a material
/// that dilates as it shears (psi > 0) sucks water and gains strength from the suction, so the
/// factor overstates that of a failure with drainage. The warning that says so, naming those
/// materials; none for another case.
std::optional<std::string> undrained_dilatancy_warning(const CaseSpec& spec);

/// `talus fos`: runs the search on a case with a `strength_reduction` section. Each trial is a
/// run in <out>/trials/F<factor>/ (run.h5, newton.log, ...); the search writes fos.log (one
/// line per trial saying why it ended), fos.csv (crest displacement against F), fos.json and
/// fos.png (scripts/plot_fos.py). A staged case runs one incremental search per stage searched
/// after, in <out>/trials/after_<stage>/, and adds fos_history.csv and fos_history.png (the
/// factor against time, scripts/plot_fos_history.py). An earlier search's directory is not
/// overwritten without `force`.
FosRunResult run_factor_of_safety(const CaseSpec& spec, const FosOptions& options);

} // namespace talus
