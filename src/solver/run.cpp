#include "talus/solver/run.hpp"

#include "run_checkpoint.hpp"
#include "run_recorder.hpp"
#include "run_stage_loops.hpp"
#include "talus/core/errors.hpp"
#include "talus/core/scene.hpp"
#include "talus/core/splitting.hpp"
#include "talus/io/progress.hpp"
#include "talus/io/results.hpp"
#include "talus/parallel/migration.hpp"
#include "talus/solver/implicit_solver.hpp"
#include "talus/solver/scene_checkpoint.hpp"
#include "talus/solver/stage_watch.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <fmt/format.h>
#include <functional>
#include <omp.h>
#include <optional>

namespace talus {

namespace fs = std::filesystem;

namespace {

using run_detail::g_interrupted;
using run_detail::LoopState;
using run_detail::Recorder;
using run_detail::set_strength;
using run_detail::StageStrength;

extern "C" void on_interrupt(int) {
  run_detail::g_interrupted = true;
}

// Result files a run owns; --force replaces exactly these and leaves anything else alone.
const char* const kResultFiles[] = {"run.h5",       "run.xmf",    "timeseries.csv",
                                    "summary.json", "newton.log", "checkpoints"};

/// An implicit run's phases and output add up to its wall time: the rest (building the scene,
/// the stepper, splitting) is `seconds_other`.
void account_for_wall_time(RunResult& result, double output_seconds) {
  auto& x = result.extra;
  if (!x.contains("seconds_material"))
    return;
  x["seconds_output"] = output_seconds;
  double accounted = output_seconds;
  for (const auto& [key, seconds] : implicit_phases(ImplicitTimings{}))
    accounted += x[key];
  if (x.contains("seconds_checkpoint"))
    accounted += x["seconds_checkpoint"];
  x["seconds_other"] = result.wall_seconds - accounted;
}

/// The stages a run goes through: the case's, or one made of its analysis and time.
std::vector<StageSpec> stages_of(const CaseSpec& spec) {
  if (!spec.stages.empty())
    return spec.stages;
  StageSpec only;
  only.analysis = spec.analysis;
  only.time = spec.time;
  return {only};
}

/// A quasi-static stage leaves the points in equilibrium with a pseudo-rate as velocity: a
/// dynamic stage after it starts them at rest, with no Newmark acceleration yet.
template <int Dim> void start_at_rest(Particles<Dim>& P) {
  std::fill(P.v.begin(), P.v.end(), Vec<Dim>::Zero());
  std::fill(P.affine_velocity.begin(), P.affine_velocity.end(), Mat<Dim>::Zero());
  P.acceleration.clear();
}

const char* analysis_name(AnalysisType a) {
  switch (a) {
  case AnalysisType::Explicit:
    return "explicit";
  case AnalysisType::ImplicitQuasistatic:
    return "implicit_quasistatic";
  case AnalysisType::ImplicitDynamic:
    return "implicit_dynamic";
  }
  return "?";
}

} // namespace

void claim_output_directory(const fs::path& dir, bool force,
                            std::span<const char* const> owned_entries) {
  std::error_code ec;
  if (!fs::exists(dir, ec))
    return;
  if (!fs::is_directory(dir, ec))
    throw InputError({"--out", 0, 0, ""},
                     fmt::format("'{}' exists and is not a directory", dir.string()));
  if (fs::is_empty(dir, ec))
    return;
  if (!force)
    throw InputError({"--out", 0, 0, ""},
                     fmt::format("output directory '{}' already holds results; choose another "
                                 "--out or pass --force to replace them",
                                 dir.string()));
  for (const char* name : owned_entries)
    fs::remove_all(dir / name, ec);
}

void prepare_output_directory(const fs::path& dir, bool force) {
  claim_output_directory(dir, force, kResultFiles);
}

void on_root(const Communicator& ranks, const std::function<void()>& work) {
  std::optional<std::string> failure;
  if (ranks.root()) {
    try {
      work();
    } catch (const InputError& e) {
      failure = e.what();
      ranks.first_message(failure);
      throw;
    }
  }
  if (const auto first = ranks.first_message(failure))
    throw InputError({"mpirun", 0, 0, ""}, *first);
}

namespace {

/// What a distributed run cannot do yet, refused before anything is written (exit 2).
void refuse_unsupported_distributed(const CaseSpec& spec, const RunOptions& options) {
  auto refuse = [](const std::string& what) {
    throw InputError({"mpirun", 0, 0, ""},
                     fmt::format("{} does not run distributed yet; run it without mpirun", what));
  };
#ifndef TALUS_HAVE_TRILINOS
  for (const StageSpec& stage : stages_of(spec))
    if (stage.analysis != AnalysisType::Explicit)
      refuse(fmt::format("an implicit analysis ('{}') in a binary without Trilinos",
                         analysis_name(stage.analysis)));
#else
  (void)spec;
#endif
  if (!options.dump_tangent.empty())
    refuse("--dump-tangent");
}

/// A resumed run's starting point: its newest valid checkpoint, read and checked against the
/// case, with the scene's points restored from it. Throws InputError (exit 2) when there is
/// no usable checkpoint or the case differs; nothing is written before.
template <int Dim>
run_detail::RunProgress resume_from_checkpoint(Scene<Dim>& scene, const fs::path& out_dir,
                                               const RunOptions& options,
                                               const Communicator& ranks) {
  std::vector<std::string> skipped;
  const CheckpointReader checkpoint = run_detail::newest_valid_checkpoint(out_dir, skipped);
  if (ranks.root())
    for (const auto& why : skipped)
      fmt::print(stderr, "talus: {}\n", why);
  run_detail::RunProgress progress = run_detail::read_progress(checkpoint);
  if (progress.dimension != Dim)
    throw InputError({"--resume", 0, 0, ""},
                     fmt::format("checkpoint '{}' is of a {}D run; the case is {}D",
                                 checkpoint.file().string(), progress.dimension, Dim));
  run_detail::check_same_case(scene.spec, progress, options.accept_changes);
  try {
    restore_scene_state(checkpoint, scene);
  } catch (const std::runtime_error& e) {
    throw InputError({"--resume", 0, 0, ""}, e.what());
  }
  // The backend the run chose by itself stays (the choice depends on the first step's size).
  if (!progress.linear_solver.empty())
    scene.spec.solver.linear_solver = progress.linear_solver;
  // As StageStrength::at: the materials as built have the factor 1 (and the return map
  // reduce_strength(1) makes may differ from it in the last bit).
  if (progress.strength_factor != 1.0)
    set_strength(scene, scene.spec, progress.strength_factor);
  // Rows and log lines written after the checkpoint are written again.
  on_root(ranks, [&] {
    for (const auto& [file, bytes] :
         {std::pair{out_dir / "timeseries.csv", progress.timeseries_bytes},
          std::pair{out_dir / "newton.log", progress.newton_log_bytes}}) {
      std::error_code ec;
      if (bytes > 0 && (!fs::exists(file, ec) || fs::file_size(file, ec) < bytes))
        throw InputError({"--resume", 0, 0, ""},
                         fmt::format("'{}' is shorter than when checkpoint '{}' was written",
                                     file.string(), checkpoint.file().string()));
      if (bytes > 0)
        fs::resize_file(file, bytes);
    }
    fmt::print(stderr, "talus: resuming from '{}' (step {}, t = {:g})\n",
               checkpoint.file().string(), progress.step, progress.stage_start_time + progress.t);
  });
  return progress;
}

/// run_case for a case of dimension Dim: the stages, each from the state the previous left.
template <int Dim> RunResult run_case_in(const CaseSpec& spec, const RunOptions& options) {
  const auto wall_start = std::chrono::steady_clock::now();
  // Everything that can reject the input happens before the first byte is written.
  Scene<Dim> scene = build_scene<Dim>(spec);
  // A distributed run: every rank built the whole scene and keeps its share; rank 0 alone
  // writes files, with every rank's points in them.
  const Communicator& ranks = Communicator::world();
  if (ranks.distributed())
    refuse_unsupported_distributed(spec, options);
  RunResult result;
  result.out_dir = options.out_dir.empty() ? fs::path("results") / spec.name : options.out_dir;
  std::optional<run_detail::RunProgress> resumed;
  // A checkpoint holds the whole run in the serial order, whatever ranks wrote it: every rank
  // restores it whole, then keeps its share.
  if (options.resume)
    resumed = resume_from_checkpoint(scene, result.out_dir, options, ranks);
  else
    on_root(ranks, [&] { prepare_output_directory(result.out_dir, options.force); });
  if (ranks.distributed())
    distribute_scene(scene, ranks);
  if (options.threads > 0)
    omp_set_num_threads(options.threads);
  else if (ranks.distributed()) // the machine's cores shared among its ranks
    omp_set_num_threads(std::max(1, omp_get_num_procs() / ranks.ranks_on_this_machine()));

  if (ranks.root())
    fs::create_directories(result.out_dir);
  ResultsWriter writer =
      !ranks.root() ? ResultsWriter(ResultsWriter::CountOnly{},
                                    resumed ? static_cast<Index>(resumed->frames.size()) : 0)
      : resumed     ? ResultsWriter(result.out_dir, run_detail::metadata_of(scene), resumed->frames)
                    : ResultsWriter(result.out_dir, run_detail::metadata_of(scene));
  const std::vector<std::string> columns =
      run_detail::timeseries_columns(scene, options.measure_stiffness);
  std::optional<TimeSeriesWriter> series_file;
  if (ranks.root())
    series_file.emplace(result.out_dir / "timeseries.csv", columns, resumed.has_value());
  else
    series_file.emplace(columns.size());
  TimeSeriesWriter& series = *series_file;
  const bool show_progress = options.progress && ranks.root();

  const OutputSpec& out = spec.output;
  g_interrupted = false;
  auto previous_sigint = std::signal(SIGINT, on_interrupt);
  auto previous_sigterm = std::signal(SIGTERM, on_interrupt);

  const std::vector<StageSpec> stages = stages_of(spec);
  const bool staged = !spec.stages.empty();
  Recorder<Dim> recorder{scene, writer, series};
  LoopState state;
  state.stop_after_step = options.stop_after_step;
  state.measure_stiffness = options.measure_stiffness;
  if (options.measure_stiffness)
    recorder.current_stiffness = &state.current_stiffness;
  result.status = "completed";
  result.particles = run_detail::point_count(scene);
  double stage_start_time = 0;
  double strength_factor = 1.0;
  double wall_before = 0; // of the run's earlier processes (a resumed run)
  std::size_t first_stage = 0;
  if (resumed) {
    const run_detail::RunProgress& r = *resumed;
    result.extra = r.extra;
    result.stages = r.stages;
    state.step = r.step;
    state.stage_first_step = r.stage_first_step;
    state.resumed_mid_stage = r.stage_started;
    state.implicit_dt = r.implicit_dt;
    state.easy_steps = r.easy_steps;
    state.continuation = r.continuation;
    state.reference_compliance = r.reference_compliance;
    state.current_stiffness = r.current_stiffness;
    stage_start_time = r.stage_start_time;
    strength_factor = r.strength_factor;
    wall_before = r.wall_seconds;
    first_stage = static_cast<std::size_t>(r.stage);
    recorder.frame_at_current_step = r.frame_at_current_step;
    recorder.last_frame_step = r.last_frame_step;
    recorder.last_frame_time = r.last_frame_time;
    recorder.frame_seconds = r.frame_seconds;
    recorder.post_seconds = r.post_seconds;
  } else {
    if (splitting_requested(spec)) {
      result.extra["particles_initial"] = static_cast<double>(result.particles);
      result.extra["splits"] = 0.0;
    }
    recorder.write_frame(0, 0.0);
  }
  std::optional<StageSummary> current;
  // Closes the stage record with why the stage ended.
  auto end_stage = [&](const std::string& why, const auto& stage_started) {
    current->end_time = stage_start_time + state.t;
    current->steps = state.step - state.stage_first_step;
    current->strength_factor = strength_factor;
    current->wall_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - stage_started).count();
    current->end = why;
    result.stages.push_back(*current);
    current.reset();
  };
  auto stage_started = std::chrono::steady_clock::now();

  // Checkpoints: the run's progress and the scene's evolving state, after a completed step
  // when due (output.checkpoint), on an interrupt and at each stage's end.
  const std::optional<CheckpointSpec>& checkpoint_spec = out.checkpoint;
  auto last_checkpoint = std::chrono::steady_clock::now();
  auto write_checkpoint = [&](std::size_t stage, bool stage_in_progress, double stage_strength,
                              const StageWatch* watch) {
    const auto start = std::chrono::steady_clock::now();
    result.extra["checkpoints"] += 1;
    run_detail::RunProgress p;
    p.case_text = spec.source_text;
    p.overrides = spec.overrides;
    p.dimension = Dim;
    p.stage = static_cast<Index>(stage);
    p.stage_started = stage_in_progress;
    p.step = state.step;
    p.stage_first_step = state.stage_first_step;
    p.t = state.t;
    p.stage_start_time = stage_start_time;
    p.strength_factor = strength_factor;
    p.stage_start_strength = stage_strength;
    p.stage_wall_seconds = std::chrono::duration<double>(start - stage_started).count();
    p.wall_seconds = std::chrono::duration<double>(start - wall_start).count() + wall_before;
    p.linear_solver = result.linear_solver;
    p.implicit_dt = state.implicit_dt;
    p.easy_steps = state.easy_steps;
    p.continuation = state.continuation;
    p.reference_compliance = state.reference_compliance;
    p.current_stiffness = state.current_stiffness;
    if (watch)
      p.watch = watch->memory();
    p.extra = result.extra;
    if (stage_in_progress && state.stage_totals)
      state.stage_totals(p.extra);
    p.stages = result.stages;
    p.frames = writer.frames();
    std::error_code ec;
    if (ranks.root()) { // the files rank 0 writes
      p.timeseries_bytes = fs::file_size(result.out_dir / "timeseries.csv");
      const fs::path log = result.out_dir / "newton.log";
      p.newton_log_bytes = fs::exists(log, ec) ? fs::file_size(log) : 0;
    }
    p.next_frame_time = recorder.next_frame_time;
    p.frame_at_current_step = recorder.frame_at_current_step;
    p.last_frame_step = recorder.last_frame_step;
    p.last_frame_time = recorder.last_frame_time;
    p.frame_seconds = recorder.frame_seconds;
    p.post_seconds = recorder.post_seconds;
    // Rank 0 writes, with every point gathered there in the serial order: the checkpoint is the
    // one a serial run writes, and resumes on any number of ranks.
    auto save = [&] {
      if (!ranks.root())
        return;
      CheckpointWriter file(run_detail::checkpoint_file(result.out_dir, state.step));
      run_detail::put_progress(file, p);
      save_scene_state(scene, file);
      file.commit();
      run_detail::prune_checkpoints(result.out_dir);
      result.extra["checkpoint_bytes"] = static_cast<double>(file.bytes());
    };
    if (scene.distributed())
      with_points_on_root(scene, save);
    else
      save();
    last_checkpoint = std::chrono::steady_clock::now();
    result.extra["seconds_checkpoint"] +=
        std::chrono::duration<double>(last_checkpoint - start).count();
  };
  try {
    for (std::size_t k = first_stage; k < stages.size() && !g_interrupted; ++k) {
      const StageSpec& stage = stages[k];
      const bool continuing = state.resumed_mid_stage;
      if (!continuing && k > 0 && stages[k - 1].analysis == AnalysisType::ImplicitQuasistatic &&
          stage.analysis != AnalysisType::ImplicitQuasistatic)
        start_at_rest(scene.particles);
      scene.spec.analysis = stage.analysis;
      scene.spec.time = stage.time;
      if (!continuing) {
        state.t = 0;
        state.stage_first_step = state.step;
      } else {
        state.t = resumed->t;
      }
      stage_started =
          std::chrono::steady_clock::now() -
          std::chrono::duration_cast<std::chrono::steady_clock::duration>(
              std::chrono::duration<double>(continuing ? resumed->stage_wall_seconds : 0.0));
      current = StageSummary{};
      current->name = stage.name;
      current->analysis = analysis_name(stage.analysis);
      current->start_time = stage_start_time;
      Progress progress(staged ? fmt::format("{} [{}]", spec.name, stage.name) : spec.name,
                        stage.time.end_time, show_progress);
      recorder.begin_stage(k, progress,
                           out.every_time ? *out.every_time
                                          : (out.every_steps ? 0.0 : stage.time.end_time / 20.0),
                           stage_start_time);
      StageWatch watch(stage, ranks);
      const double start_strength = continuing ? resumed->stage_start_strength : strength_factor;
      StageStrength<Dim> strength(scene, spec, strength_factor, start_strength,
                                  stage.strength_factor.value_or(start_strength));
      if (continuing) {
        recorder.next_frame_time = resumed->next_frame_time;
        watch.recall(resumed->watch);
      }
      if (checkpoint_spec)
        state.checkpoint = [&, k] {
          bool due =
              g_interrupted || watch.out_of_time() ||
              (checkpoint_spec->every_steps && state.step % *checkpoint_spec->every_steps == 0) ||
              (checkpoint_spec->every_seconds &&
               std::chrono::duration<double>(std::chrono::steady_clock::now() - last_checkpoint)
                       .count() >= *checkpoint_spec->every_seconds);
          due = ranks.any(due); // the ranks' clocks differ: one rank's due is everyone's
          if (due)
            write_checkpoint(k, true, strength.start(), &watch);
        };
      // From here on strength_factor follows the factor the materials have.
      if (stage.analysis == AnalysisType::Explicit) {
        strength.at(1.0);
        run_explicit(scene, recorder, state, result, watch);
      } else {
        run_implicit(scene, recorder, state, result, result.out_dir, watch, strength, k == 0,
                     options.dump_tangent);
      }
      state.checkpoint = nullptr;
      // Ended by its end time or at rest, not cut short: the next checkpoint starts the next.
      const bool stage_complete =
          !state.stopped && !watch.out_of_time() &&
          (!watch.reason().empty() || state.t >= stage.time.end_time * (1.0 - 1e-14));
      if (g_interrupted)
        recorder.final_frame(state.step, state.t);
      const std::string why = g_interrupted            ? "interrupted"
                              : state.stopped          ? *state.stopped
                              : watch.reason().empty() ? "end_time reached"
                                                       : watch.reason();
      if (staged)
        progress.finish("stage ended: " + why);
      end_stage(why, stage_started);
      stage_start_time += state.t;
      state.t = 0;
      if (watch.out_of_time()) {
        result.status = "interrupted";
        result.message = fmt::format("stage '{}' stopped: {}", stage.name, why);
        result.exit_code = kExitOther;
        break;
      }
      if (state.stopped) {
        result.status = "stopped";
        result.message = *state.stopped;
        result.exit_code = kExitOther;
        break;
      }
      if (stage_complete && checkpoint_spec)
        write_checkpoint(k + 1, false, strength_factor, nullptr);
    }
    if (g_interrupted) {
      result.status = "interrupted";
      result.message =
          fmt::format("interrupted at step {}, t = {:g}", state.step, stage_start_time + state.t);
      result.exit_code = kExitOther;
    }
  } catch (const NumericalError& err) {
    state.checkpoint = nullptr;
    state.stage_totals = nullptr;
    result.status = "numerical_failure";
    if (dynamic_cast<const NewtonStall*>(&err))
      result.extra["newton_stalled"] = 1.0;
    result.message =
        fmt::format("step {}, t = {:g}{}: {}", state.step + 1, stage_start_time + state.t,
                    staged ? fmt::format(" (stage '{}')", current->name) : "", err.what());
    result.exit_code = kExitNumerical;
    if (current)
      end_stage(fmt::format("failed: {}", err.what()), stage_started);
    stage_start_time += state.t;
    state.t = 0;
  }
  if (std::isfinite(state.current_stiffness))
    result.extra["current_stiffness"] = state.current_stiffness;
  if (out.stress_recovery || out.voxels)
    result.extra["seconds_post_processing"] = recorder.post_seconds;
  // With splitting, `particles` is the count at the end (particles_initial the one at t = 0).
  result.particles = run_detail::point_count(scene);
  if constexpr (Dim == 2) {
    if (options.final_state)
      options.final_state(scene);
  } else if (options.final_state_3d) {
    options.final_state_3d(scene);
  }
  std::signal(SIGINT, previous_sigint);
  std::signal(SIGTERM, previous_sigterm);

  result.steps = state.step;
  result.final_time = stage_start_time + state.t;
  result.frames = writer.frames_written();
  result.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count() +
      wall_before;
  account_for_wall_time(result, recorder.frame_seconds);
  if (ranks.distributed()) {
    // Each rank's own share, then the largest: a rank that waits long carries the imbalance.
    result.extra["ranks"] = ranks.size();
    result.extra["seconds_communication"] = ranks.communication_seconds();
    result.extra["seconds_communication_max"] = ranks.max(ranks.communication_seconds());
  }
  Progress(spec.name, 0, show_progress)
      .finish(result.status == "completed"
                  ? fmt::format("done: {} steps, {} frames, {:.2f} s", state.step, result.frames,
                                result.wall_seconds)
                  : result.status + ": " + result.message);

  RunSummary summary;
  summary.case_name = spec.name;
  summary.status = result.status;
  summary.message = result.message;
  summary.steps = result.steps;
  summary.final_time = result.final_time;
  summary.particles = result.particles;
  summary.frames = result.frames;
  summary.wall_seconds = result.wall_seconds;
  summary.linear_solver = result.linear_solver;
  summary.extra = result.extra;
  if (staged)
    summary.stages = result.stages;
  if (ranks.root())
    write_summary_json(result.out_dir / "summary.json", summary);
  // Every rank may read the results next (verification): they are complete when it returns.
  ranks.barrier();
  return result;
}

} // namespace

RunResult run_case(const CaseSpec& spec, const RunOptions& options) {
  return spec.dimension == 3 ? run_case_in<3>(spec, options) : run_case_in<2>(spec, options);
}

} // namespace talus
