#pragma once
// Internal to run_case (src/solver/run.cpp): one run of a case of dimension Dim, from building
// its scene to summary.json. The constructor does everything that can reject the input before
// a byte is written (the scene, a resume's checkpoint, the output directory); execute() steps
// the stages, each from the state the previous one left, with checkpoints when due.
#include "run_checkpoint.hpp"
#include "run_stage_loops.hpp"
#include "talus/io/results.hpp"
#include "talus/scene/scene.hpp"
#include "talus/solver/run.hpp"

#include <chrono>
#include <optional>
#include <string>
#include <vector>

namespace talus::run_detail {

template <int Dim> class Run {
public:
  Run(const CaseSpec& spec, const RunOptions& options);
  RunResult execute();

private:
  using Clock = std::chrono::steady_clock;

  /// Steps stage k; false when the run ends with it (out of time, or stopped by its hook).
  bool run_stage(std::size_t k);
  /// Closes the current stage's record with why it ended.
  void end_stage(const std::string& why);
  /// The run's progress now, for a checkpoint of stage `stage` (in progress or about to start).
  RunProgress progress_now(std::size_t stage, bool in_progress, double stage_strength,
                           const StageWatch* watch) const;
  void write_checkpoint(std::size_t stage, bool in_progress, double stage_strength,
                        const StageWatch* watch);
  /// The result's totals, the final progress line and summary.json.
  void finish();

  const CaseSpec& spec_;
  const RunOptions& options_;
  const Clock::time_point wall_start_ = Clock::now();
  Scene<Dim> scene_;
  const Communicator& ranks_;
  RunResult result_;
  std::optional<RunProgress> resumed_; ///< the checkpoint a resumed run started from
  std::optional<ResultsWriter> writer_;
  std::optional<TimeSeriesWriter> series_;
  std::optional<Recorder<Dim>> recorder_;
  LoopState state_;
  std::vector<StageSpec> stages_;
  double stage_start_time_ = 0;
  double strength_factor_ = 1.0;
  double wall_before_ = 0; ///< of the run's earlier processes (a resumed run)
  std::optional<StageSummary> current_;
  Clock::time_point stage_started_ = Clock::now();
  Clock::time_point last_checkpoint_ = Clock::now();
};

} // namespace talus::run_detail
