#pragma once
// Factor of safety by strength reduction (Griffiths & Lane, Geotechnique 49 (1999) 387): the
// case is loaded quasi-statically, from scratch, with every frictional material's strength
// divided by a trial factor F (c / F, tan(phi) / F); the factor of safety is the smallest F at
// which the loading fails. A trial fails when Newton does not converge at the smallest load
// step (no equilibrium: the mechanism runs away) or, if the case sets a limit, as soon as the
// crest has moved further than that after a converged load step (a mechanism that slides and
// re-stabilises, which the updated-Lagrangian MPM allows with a patient enough Newton; the
// trial stops there instead of carrying the rest of its load). The search brackets the
// critical factor and bisects.
#include "talus/io/case_spec.hpp"
#include "talus/solver/run.hpp"

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace talus {

/// The case with every tresca, mohr_coulomb and drucker_prager material weakened by `factor`:
/// c / F, phi_F = atan(tan(phi) / F), the residual strength likewise; the dilation angle, a
/// flow parameter and not a strength, is kept unless it exceeds the reduced (peak or residual)
/// phi, where it is capped (the models require psi <= phi).
CaseSpec reduce_strength(const CaseSpec& spec, double factor);
/// One material weakened the same way (unchanged unless tresca, mohr_coulomb, drucker_prager).
MaterialSpec reduce_strength(const MaterialSpec& material, double factor);

/// What the loading at one trial factor found.
struct StrengthTrial {
  double factor = 0;
  bool failed = false;
  std::string reason;                ///< why the trial ended (the log line)
  double load_reached = 0;           ///< t / end_time of the last converged step
  double crest_dx = 0, crest_dy = 0; ///< m, crest probe displacement at the last converged step
  Index load_steps = 0, newton_iterations = 0, cutbacks = 0;
  double seconds = 0; ///< wall time of the trial
  double crest_displacement() const;
};

/// What a trial's run says about the trial factor: it stood (the full load, the crest within
/// `displacement_limit`) or failed, and why: interrupted, stopped by the crest limit during
/// the loading (status "stopped"), failed numerically (Newton at min_dt, max_steps, the state
/// guard), or converged with the crest beyond the limit. `crest_dx`, `crest_dy`: the probe's
/// displacement at the run's last converged step.
StrengthTrial classify_trial(const StrengthReductionSpec& settings, double factor,
                             const RunResult& run, double end_time, double crest_dx,
                             double crest_dy);

/// The outcome of the search.
struct FactorOfSafety {
  bool bracketed = false;            ///< a standing and a failing factor at most `tolerance` apart
  double lower = 0;                  ///< the largest factor that stood
  double upper = 0;                  ///< the smallest factor that failed
  std::string message;               ///< why the search ended
  std::vector<StrengthTrial> trials; ///< in the order they ran
  /// The bracket's midpoint, the reported factor of safety.
  double value() const { return 0.5 * (lower + upper); }
};

/// The search, independent of how a trial runs: `lower` must stand (else the factor of safety
/// is below the range and the search stops); `upper` is raised by half while it stands; then
/// the bracket is bisected until it is at most `tolerance` wide. At most `max_trials` trials,
/// so the search always ends. `on_trial` (may be empty) sees each trial as it finishes.
FactorOfSafety search_factor_of_safety(const StrengthReductionSpec& settings,
                                       const std::function<StrengthTrial(double)>& trial,
                                       const std::function<void(const StrengthTrial&)>& on_trial);

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
};

FactorOfSafety incremental_factor_of_safety(const CaseSpec& spec, const std::filesystem::path& dir,
                                            const FosOptions& search, bool& interrupted);

/// A trial's run into options.out_dir. Resuming a search (search.resume), a run that finished
/// there is taken from its summary.json as it is, one that was cut short continues from its
/// newest checkpoint, and one without a checkpoint starts again.
RunResult run_or_resume_trial(const CaseSpec& spec, RunOptions options, const FosOptions& search);

struct FosRunResult {
  FactorOfSafety fos;
  std::filesystem::path out_dir;
  double wall_seconds = 0;
  /// Processor time of the search (user + system, all threads): on a machine shared with other
  /// work the wall time says little, this is the search's own cost.
  double cpu_seconds = 0;
  Index newton_iterations = 0; ///< summed over the trials
  int exit_code = 0;           ///< 0 bracketed, 3 not bracketed, 1 interrupted
};

/// `talus fos`: runs the search on a case with a `strength_reduction` section. Each trial is a
/// run in <out>/trials/F<factor>/ (run.h5, newton.log, ...); the search writes fos.log (one
/// line per trial saying why it ended), fos.csv (crest displacement against F), fos.json and
/// fos.png (scripts/plot_fos.py). An earlier search's directory is not overwritten without
/// `force`.
FosRunResult run_factor_of_safety(const CaseSpec& spec, const FosOptions& options);

} // namespace talus
