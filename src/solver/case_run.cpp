// One run of a case (case_run.hpp).
#include "case_run.hpp"

#include "talus/core/errors.hpp"
#include "talus/io/progress.hpp"
#include "talus/scene/migration.hpp"
#include "talus/solver/failure_hints.hpp"
#include "talus/solver/scene_checkpoint.hpp"
#include "talus/solver/stage_watch.hpp"

#include <algorithm>
#include <cmath>
#include <csignal>
#include <fmt/format.h>
#include <omp.h>

namespace talus::run_detail {

namespace fs = std::filesystem;

namespace {

extern "C" void on_interrupt(int) {
  g_interrupted = true;
}

/// SIGINT and SIGTERM set g_interrupted while the run steps; the previous handlers come back
/// when it ends, however it ends.
class InterruptHandlers {
public:
  InterruptHandlers()
      : sigint_(std::signal(SIGINT, on_interrupt)), sigterm_(std::signal(SIGTERM, on_interrupt)) {
    g_interrupted = false;
  }
  ~InterruptHandlers() {
    std::signal(SIGINT, sigint_);
    std::signal(SIGTERM, sigterm_);
  }
  InterruptHandlers(const InterruptHandlers&) = delete;
  InterruptHandlers& operator=(const InterruptHandlers&) = delete;

private:
  void (*sigint_)(int);
  void (*sigterm_)(int);
};

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
  for (int f = 0; f < face_count(spec.dimension); ++f)
    if (spec.boundaries[f] == FaceCondition::Platen)
      refuse(fmt::format("a platen (boundaries.{})", face_name(f)));
}

/// A resumed run's starting point: its newest valid checkpoint, read and checked against the
/// case, with the scene's points restored from it. Throws InputError (exit 2) when there is
/// no usable checkpoint or the case differs; nothing is written before.
template <int Dim>
RunProgress resume_from_checkpoint(Scene<Dim>& scene, const fs::path& out_dir,
                                   const RunOptions& options, const Communicator& ranks) {
  std::vector<std::string> skipped;
  const CheckpointReader checkpoint = newest_valid_checkpoint(out_dir, skipped);
  if (ranks.root())
    for (const auto& why : skipped)
      fmt::print(stderr, "talus: {}\n", why);
  RunProgress progress = read_progress(checkpoint);
  if (progress.dimension != Dim)
    throw InputError({"--resume", 0, 0, ""},
                     fmt::format("checkpoint '{}' is of a {}D run; the case is {}D",
                                 checkpoint.file().string(), progress.dimension, Dim));
  check_same_case(scene.spec, progress, options.accept_changes);
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
               checkpoint.file().string(), progress.loop.step,
               progress.stage_start_time + progress.loop.t);
  });
  return progress;
}

double seconds_between(std::chrono::steady_clock::time_point a,
                       std::chrono::steady_clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

} // namespace

template <int Dim>
Run<Dim>::Run(const CaseSpec& spec, const RunOptions& options)
    : spec_(spec), options_(options), scene_(build_scene<Dim>(spec)), ranks_(Communicator::world()),
      stages_(stages_of(spec)) {
  // A distributed run: every rank built the whole scene and keeps its share; rank 0 alone
  // writes files, with every rank's points in them.
  if (ranks_.distributed())
    refuse_unsupported_distributed(spec, options);
  result_.out_dir = options.out_dir.empty() ? fs::path("results") / spec.name : options.out_dir;
  // A checkpoint holds the whole run in the serial order, whatever ranks wrote it: every rank
  // restores it whole, then keeps its share.
  if (options.resume)
    resumed_ = resume_from_checkpoint(scene_, result_.out_dir, options, ranks_);
  else
    on_root(ranks_, [&] { prepare_output_directory(result_.out_dir, options.force); });
  if (ranks_.distributed())
    distribute_scene(scene_, ranks_);
  if (options.threads > 0)
    omp_set_num_threads(options.threads);
  else if (ranks_.distributed()) // the machine's cores shared among its ranks
    omp_set_num_threads(std::max(1, omp_get_num_procs() / ranks_.ranks_on_this_machine()));

  if (ranks_.root())
    fs::create_directories(result_.out_dir);
  if (!ranks_.root())
    writer_.emplace(ResultsWriter::CountOnly{},
                    resumed_ ? static_cast<Index>(resumed_->frames.size()) : 0);
  else if (resumed_)
    writer_.emplace(result_.out_dir, metadata_of(scene_), resumed_->frames);
  else
    writer_.emplace(result_.out_dir, metadata_of(scene_));
  const std::vector<std::string> columns = timeseries_columns(scene_, options.measure_stiffness);
  if (ranks_.root())
    series_.emplace(result_.out_dir / "timeseries.csv", columns, resumed_.has_value());
  else
    series_.emplace(columns.size());
  recorder_.emplace(resumed_ ? resumed_->schedule : FrameSchedule{}, scene_, *writer_, *series_);

  state_.stop_after_step = options.stop_after_step;
  state_.measure_stiffness = options.measure_stiffness;
  state_.measure_stiffness_from_stage = options.measure_stiffness_from_stage;
  if (options.measure_stiffness)
    recorder_->current_stiffness = &state_.current_stiffness;
  result_.status = "completed";
  result_.particles = point_count(scene_);
  if (resumed_) {
    const RunProgress& r = *resumed_;
    static_cast<LoopCounters&>(state_) = r.loop;
    state_.resumed_mid_stage = r.stage_started;
    result_.extra = r.extra;
    result_.stages = r.stages;
    stage_start_time_ = r.stage_start_time;
    strength_factor_ = r.strength_factor;
    wall_before_ = r.wall_seconds;
  } else if (splitting_requested(spec)) {
    result_.extra["particles_initial"] = static_cast<double>(result_.particles);
    result_.extra["splits"] = 0.0;
  }
}

template <int Dim> RunResult Run<Dim>::execute() {
  const InterruptHandlers interrupts;
  if (!resumed_)
    recorder_->write_frame(0, 0.0);
  const std::size_t first_stage = resumed_ ? static_cast<std::size_t>(resumed_->stage) : 0;
  try {
    for (std::size_t k = first_stage; k < stages_.size() && !g_interrupted; ++k)
      if (!run_stage(k))
        break;
    if (g_interrupted) {
      result_.status = "interrupted";
      result_.message = fmt::format("interrupted at step {}, t = {:g}", state_.step,
                                    stage_start_time_ + state_.t);
      result_.exit_code = kExitOther;
    }
  } catch (const NumericalError& err) {
    state_.checkpoint = nullptr;
    state_.stage_totals = nullptr;
    result_.status = "numerical_failure";
    const bool stalled = dynamic_cast<const NewtonStall*>(&err) != nullptr;
    if (stalled)
      result_.extra["newton_stalled"] = 1.0;
    const FailureContext context{scene_.spec.analysis, stalled};
    const auto* point = dynamic_cast<const PointFailure*>(&err);
    const std::string causes = describe_likely_causes(likely_failure_causes(scene_.spec, context));
    result_.message = fmt::format(
        "step {}, t = {:g}{}: {}{}{}", state_.step + 1, stage_start_time_ + state_.t,
        spec_.stages.empty() ? "" : fmt::format(" (stage '{}')", current_->name), err.what(),
        point ? where_point_is(scene_, point->point()) : "", causes.empty() ? "" : ". " + causes);
    result_.exit_code = kExitNumerical;
    if (current_)
      end_stage(fmt::format("failed: {}", err.what()));
    stage_start_time_ += state_.t;
    state_.t = 0;
  }
  finish();
  return result_;
}

template <int Dim> bool Run<Dim>::run_stage(std::size_t k) {
  const StageSpec& stage = stages_[k];
  const bool continuing = state_.resumed_mid_stage;
  if (!continuing && k > 0 && stages_[k - 1].analysis == AnalysisType::ImplicitQuasistatic &&
      stage.analysis != AnalysisType::ImplicitQuasistatic)
    start_at_rest(scene_.particles);
  scene_.spec.analysis = stage.analysis;
  scene_.spec.time = stage.time;
  if (!continuing) {
    state_.t = 0;
    state_.stage_first_step = state_.step;
  }
  stage_started_ =
      Clock::now() - std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(
                         continuing ? resumed_->stage_wall_seconds : 0.0));
  current_ = StageSummary{};
  current_->name = stage.name;
  current_->analysis = analysis_name(stage.analysis);
  current_->start_time = stage_start_time_;
  const bool staged = !spec_.stages.empty();
  Progress progress(staged ? fmt::format("{} [{}]", spec_.name, stage.name) : spec_.name,
                    stage.time.end_time, options_.progress && ranks_.root());
  const OutputSpec& out = spec_.output;
  recorder_->begin_stage(k, progress,
                         out.every_time ? *out.every_time
                                        : (out.every_steps ? 0.0 : stage.time.end_time / 20.0),
                         stage_start_time_);
  StageWatch watch(stage, ranks_);
  const double start_strength = continuing ? resumed_->stage_start_strength : strength_factor_;
  StageStrength<Dim> strength(scene_, spec_, strength_factor_, start_strength,
                              stage.strength_factor.value_or(start_strength));
  if (continuing) {
    recorder_->next_frame_time = resumed_->schedule.next_frame_time;
    watch.recall(resumed_->watch);
  }
  if (out.checkpoint)
    state_.checkpoint = [&, k, every = *out.checkpoint] {
      bool due = g_interrupted || watch.out_of_time() ||
                 (every.every_steps && state_.step % *every.every_steps == 0) ||
                 (every.every_seconds &&
                  seconds_between(last_checkpoint_, Clock::now()) >= *every.every_seconds);
      due = ranks_.any(due); // the ranks' clocks differ: one rank's due is everyone's
      if (due)
        write_checkpoint(k, true, strength.start(), &watch);
    };
  StageWater<Dim> water(scene_, spec_, stages_, k);
  // From here on strength_factor_ follows the factor the materials have.
  if (stage.analysis == AnalysisType::Explicit) {
    strength.at(1.0);
    water.at(1.0);
    run_explicit(scene_, *recorder_, state_, result_, watch);
  } else {
    run_implicit(scene_, *recorder_, state_, result_, result_.out_dir, watch, strength, water,
                 k == 0, options_.dump_tangent);
  }
  state_.checkpoint = nullptr;
  // Ended by its end time or at rest, not cut short: the next checkpoint starts the next.
  const bool stage_complete =
      !state_.stopped && !watch.out_of_time() &&
      (!watch.reason().empty() || state_.t >= stage.time.end_time * (1.0 - 1e-14));
  if (g_interrupted)
    recorder_->final_frame(state_.step, state_.t);
  const std::string why = g_interrupted            ? "interrupted"
                          : state_.stopped         ? *state_.stopped
                          : watch.reason().empty() ? "end_time reached"
                                                   : watch.reason();
  if (staged)
    progress.finish("stage ended: " + why);
  end_stage(why);
  stage_start_time_ += state_.t;
  state_.t = 0;
  if (watch.out_of_time()) {
    result_.status = "interrupted";
    result_.message = fmt::format("stage '{}' stopped: {}", stage.name, why);
    result_.exit_code = kExitOther;
    return false;
  }
  if (state_.stopped) {
    result_.status = "stopped";
    result_.message = *state_.stopped;
    result_.exit_code = kExitOther;
    return false;
  }
  if (stage_complete && out.checkpoint)
    write_checkpoint(k + 1, false, strength_factor_, nullptr);
  return true;
}

template <int Dim> void Run<Dim>::end_stage(const std::string& why) {
  current_->end_time = stage_start_time_ + state_.t;
  current_->steps = state_.step - state_.stage_first_step;
  current_->strength_factor = strength_factor_;
  current_->wall_seconds = seconds_between(stage_started_, Clock::now());
  current_->end = why;
  result_.stages.push_back(*current_);
  current_.reset();
}

template <int Dim>
RunProgress Run<Dim>::progress_now(std::size_t stage, bool in_progress, double stage_strength,
                                   const StageWatch* watch) const {
  const auto now = Clock::now();
  RunProgress p;
  p.case_text = spec_.source_text;
  p.overrides = spec_.overrides;
  p.dimension = Dim;
  p.stage = static_cast<Index>(stage);
  p.stage_started = in_progress;
  p.loop = state_;
  p.stage_start_time = stage_start_time_;
  p.strength_factor = strength_factor_;
  p.stage_start_strength = stage_strength;
  p.stage_wall_seconds = seconds_between(stage_started_, now);
  p.wall_seconds = seconds_between(wall_start_, now) + wall_before_;
  p.linear_solver = result_.linear_solver;
  if (watch)
    p.watch = watch->memory();
  p.extra = result_.extra;
  if (in_progress && state_.stage_totals)
    state_.stage_totals(p.extra);
  p.stages = result_.stages;
  p.frames = writer_->frames();
  if (ranks_.root()) { // the files rank 0 writes
    std::error_code ec;
    p.timeseries_bytes = fs::file_size(result_.out_dir / "timeseries.csv");
    const fs::path log = result_.out_dir / "newton.log";
    p.newton_log_bytes = fs::exists(log, ec) ? fs::file_size(log) : 0;
  }
  p.schedule = *recorder_;
  return p;
}

template <int Dim>
void Run<Dim>::write_checkpoint(std::size_t stage, bool in_progress, double stage_strength,
                                const StageWatch* watch) {
  const auto start = Clock::now();
  result_.extra["checkpoints"] += 1;
  const RunProgress p = progress_now(stage, in_progress, stage_strength, watch);
  // Rank 0 writes, with every point gathered there in the serial order: the checkpoint is the
  // one a serial run writes, and resumes on any number of ranks.
  auto save = [&] {
    if (!ranks_.root())
      return;
    CheckpointWriter file(checkpoint_file(result_.out_dir, state_.step));
    put_progress(file, p);
    save_scene_state(scene_, file);
    file.commit();
    prune_checkpoints(result_.out_dir);
    result_.extra["checkpoint_bytes"] = static_cast<double>(file.bytes());
  };
  if (scene_.distributed())
    with_points_on_root(scene_, save);
  else
    save();
  last_checkpoint_ = Clock::now();
  result_.extra["seconds_checkpoint"] += seconds_between(start, last_checkpoint_);
}

template <int Dim> void Run<Dim>::finish() {
  if (std::isfinite(state_.current_stiffness))
    result_.extra["current_stiffness"] = state_.current_stiffness;
  if (spec_.output.stress_recovery || spec_.output.voxels)
    result_.extra["seconds_post_processing"] = recorder_->post_seconds;
  // With splitting, `particles` is the count at the end (particles_initial the one at t = 0).
  result_.particles = point_count(scene_);
  if constexpr (Dim == 2) {
    if (options_.final_state)
      options_.final_state(scene_);
  } else if (options_.final_state_3d) {
    options_.final_state_3d(scene_);
  }
  result_.steps = state_.step;
  result_.final_time = stage_start_time_ + state_.t;
  result_.frames = writer_->frames_written();
  result_.wall_seconds = seconds_between(wall_start_, Clock::now()) + wall_before_;
  account_for_wall_time(result_, recorder_->frame_seconds);
  if (ranks_.distributed()) {
    // Each rank's own share, then the largest: a rank that waits long carries the imbalance.
    result_.extra["ranks"] = ranks_.size();
    result_.extra["seconds_communication"] = ranks_.communication_seconds();
    result_.extra["seconds_communication_max"] = ranks_.max(ranks_.communication_seconds());
  }
  Progress(spec_.name, 0, options_.progress && ranks_.root())
      .finish(result_.status == "completed"
                  ? fmt::format("done: {} steps, {} frames, {:.2f} s", state_.step, result_.frames,
                                result_.wall_seconds)
                  : result_.status + ": " + result_.message);

  RunSummary summary;
  summary.case_name = spec_.name;
  summary.status = result_.status;
  summary.message = result_.message;
  summary.steps = result_.steps;
  summary.final_time = result_.final_time;
  summary.particles = result_.particles;
  summary.frames = result_.frames;
  summary.wall_seconds = result_.wall_seconds;
  summary.linear_solver = result_.linear_solver;
  summary.extra = result_.extra;
  if (!spec_.stages.empty())
    summary.stages = result_.stages;
  if (ranks_.root())
    write_summary_json(result_.out_dir / "summary.json", summary);
  // Every rank may read the results next (verification): they are complete when it returns.
  ranks_.barrier();
}

template class Run<2>;
template class Run<3>;

} // namespace talus::run_detail
