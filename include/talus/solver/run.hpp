#pragma once
// Runs one case end to end: builds the scene, steps the solver, writes run.h5/run.xmf frames,
// timeseries.csv rows and summary.json, and shows progress. Bad input surfaces as InputError
// before anything is written; numerical failure ends the run with the earlier frames intact.
#include "talus/io/results.hpp"
#include "talus/parallel/communicator.hpp"
#include "talus/spec/case_spec.hpp"

#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <span>
#include <string>

namespace talus {

template <int Dim> struct Scene;

/// A probe's point at the start of the run and now (z = 0 in 2D).
struct ProbeState {
  std::string name;
  Vec3 initial;
  Vec3 current;
};

/// What RunOptions::stop_after_step sees after a completed step.
struct StepState {
  std::span<const ProbeState> probes; ///< the probes' points at the start and now
  double time = 0;                    ///< the run's time
  /// Bergan's current stiffness parameter of a run that measures it (RunOptions::
  /// measure_stiffness): the compliance under the load of the run's first measured step over
  /// that of this one, 1 while the response is linear, falling towards 0 as the body loses its
  /// stiffness to a mechanism; NaN when not measured.
  double current_stiffness = 0;
};

struct RunOptions {
  std::filesystem::path out_dir; ///< empty: results/<case name>
  bool force = false;            ///< replace the result files of an earlier run in out_dir
  int threads = 0;               ///< OpenMP threads; 0 keeps the OpenMP default
  bool progress = true;          ///< progress line (terminal) or periodic log lines
  /// Implicit runs: where to write the last Newton iteration's tangent (Matrix Market), for
  /// timing the linear solver on a real system (bench/bench_dumped_tangent.cpp); empty: none.
  std::filesystem::path dump_tangent{};
  /// Continue the run in out_dir (which must be given) from its newest valid checkpoint
  /// (output.checkpoint): frames, timeseries.csv, newton.log and summary.json go on from there.
  bool resume = false;
  /// With resume: allow the case to differ from the checkpoint's in the keys that may safely
  /// change (end times, max_steps, wall-time limits, output); others are always refused.
  bool accept_changes = false;
  /// Called with the state a 2D (3D) run ended in (any status), before summary.json is
  /// written: lets a caller (talus adapt) inspect the points without reading the results back.
  std::function<void(const Scene<2>&)> final_state{};
  std::function<void(const Scene<3>&)> final_state_3d{};
  /// Consulted after each completed step (a converged one in the implicit analyses): a message
  /// ends the run there, with status "stopped" and the message as RunResult::message, after
  /// that step's time-series row and frame are written (talus fos: a trial that has lost its
  /// stiffness or whose crest has slid too far need not carry the rest of its load).
  std::function<std::optional<std::string>(const StepState&)> stop_after_step{};
  /// Quasi-static steps measure the current stiffness (StepState::current_stiffness, the
  /// `current_stiffness` column of timeseries.csv): one more linear solve per step.
  bool measure_stiffness = false;
  /// The stiffness is measured from this stage on (its first measured step the reference): a
  /// history before it (a coupled one, whose u-p tangent is another stiffness) is not.
  std::size_t measure_stiffness_from_stage = 0;
};

struct RunResult {
  std::filesystem::path out_dir;
  /// "completed", "numerical_failure", "interrupted" or "stopped" (by stop_after_step)
  std::string status;
  std::string message;
  Index steps = 0;
  double final_time = 0;
  Index frames = 0;
  Index particles = 0;
  double wall_seconds = 0;
  int exit_code = 0;         ///< 0, 1 (interrupted or stopped) or 3 (numerical failure)
  std::string linear_solver; ///< implicit: the backend used (chosen or automatic); else empty
  std::map<std::string, double> extra; ///< solver statistics, also written to summary.json
  std::vector<StageSummary> stages;    ///< staged cases: each stage that ran, and why it ended
};

/// Checks that `dir` may receive results (absent, empty, or `force`); throws InputError. With
/// `force`, removes exactly the entries a command owns there (files or folders), nothing else.
void claim_output_directory(const std::filesystem::path& dir, bool force,
                            std::span<const char* const> owned_entries);

/// claim_output_directory for the files of one run (run.h5, run.xmf, timeseries.csv, ...).
void prepare_output_directory(const std::filesystem::path& dir, bool force);

RunResult run_case(const CaseSpec& spec, const RunOptions& options);

/// Runs `work` (file-system work: claiming a directory, writing a file) on rank 0 alone; an
/// InputError there stops every rank with its message. Collective in a distributed run.
void on_root(const Communicator& ranks, const std::function<void()>& work);

} // namespace talus
