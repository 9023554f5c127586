#pragma once
// Internal to run_case (src/solver/run.cpp, case_run.hpp): what a checkpoint holds of a run beyond
// the scene's points (scene_checkpoint.hpp), where the checkpoints live, and how a resume finds the
// newest good one and checks the case against it. Layout: docs/output-format.md.
#include "run_state.hpp"
#include "talus/io/checkpoint_file.hpp"
#include "talus/io/results.hpp"
#include "talus/solver/implicit_solver.hpp"
#include "talus/solver/stage_watch.hpp"

#include <filesystem>
#include <limits>
#include <map>
#include <string>
#include <vector>

namespace talus::run_detail {

/// The run's own state at a checkpoint: where it is, what it has written, what it has counted.
struct RunProgress {
  // --- the case the run was started with -----------------------------------------------------
  std::string case_text;
  std::vector<std::string> overrides;
  int dimension = 2;
  // --- where the run is ----------------------------------------------------------------------
  Index stage = 0;            ///< the stage in progress, or the next one at a stage boundary
  bool stage_started = false; ///< false: the checkpoint is at the start of `stage`
  LoopCounters loop;
  double stage_start_time = 0;
  double strength_factor = 1;      ///< the materials' strength factor now
  double stage_start_strength = 1; ///< the factor the stage started from
  double stage_wall_seconds = 0;   ///< spent in the stage so far
  double wall_seconds = 0;         ///< spent in the run so far
  std::string linear_solver;       ///< implicit: the backend the run chose
  StageWatch::Memory watch{};
  // --- what it has written and counted -------------------------------------------------------
  std::map<std::string, double> extra; ///< summary.json's numbers so far
  std::vector<StageSummary> stages;    ///< the stages that ended
  std::vector<ResultsWriter::FrameRecord> frames;
  std::uintmax_t timeseries_bytes = 0; ///< timeseries.csv's length
  std::uintmax_t newton_log_bytes = 0; ///< newton.log's length (0: none)
  FrameSchedule schedule;              ///< the recorder's
};

/// The directory of a run's checkpoints.
std::filesystem::path checkpoint_dir(const std::filesystem::path& out_dir);

/// Puts `progress` into `out` (as the entry "run", JSON text).
void put_progress(CheckpointWriter& out, const RunProgress& progress);
RunProgress read_progress(const CheckpointReader& in);

/// The file of the checkpoint after `step` steps (its folder created).
std::filesystem::path checkpoint_file(const std::filesystem::path& out_dir, Index step);

/// Removes all but the newest two checkpoints.
void prune_checkpoints(const std::filesystem::path& out_dir);

/// The newest checkpoint of the run in out_dir that reads back whole; the ones skipped on the
/// way, each with why, in `skipped`. Throws InputError (key --resume) when there is none.
CheckpointReader newest_valid_checkpoint(const std::filesystem::path& out_dir,
                                         std::vector<std::string>& skipped);

/// Throws InputError (key --resume) naming the keys where `spec` differs from the case the
/// checkpoint's run started with, unless every difference is a safe one and `accept_changes`.
void check_same_case(const CaseSpec& spec, const RunProgress& progress, bool accept_changes);

} // namespace talus::run_detail
