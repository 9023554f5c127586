#include "talus/solver/run.hpp"

#include "run_recorder.hpp"
#include "talus/core/errors.hpp"
#include "talus/core/scene.hpp"
#include "talus/core/splitting.hpp"
#include "talus/io/progress.hpp"
#include "talus/io/results.hpp"
#include "talus/material/plastic_material.hpp"
#include "talus/post/stress_recovery.hpp"
#include "talus/post/voxels.hpp"
#include "talus/solver/explicit_solver.hpp"
#include "talus/solver/implicit_solver.hpp"
#include "talus/solver/stage_watch.hpp"
#include "talus/solver/state_guard.hpp"
#include "talus/solver/strength_reduction.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <fmt/format.h>
#include <fstream>
#include <omp.h>
#include <optional>

namespace talus {

namespace fs = std::filesystem;

namespace {

using run_detail::Recorder;

std::atomic<bool> g_interrupted{false};
extern "C" void on_interrupt(int) {
  g_interrupted = true;
}

// Result files a run owns; --force replaces exactly these and leaves anything else alone.
const char* const kResultFiles[] = {"run.h5", "run.xmf", "timeseries.csv", "summary.json",
                                    "newton.log"};

struct LoopState {
  double t = 0;               ///< the stage's time
  Index step = 0;             ///< steps of the whole run
  Index stage_first_step = 0; ///< `step` when the current stage began
  /// RunOptions::stop_after_step, and what it said when it ended the run.
  std::function<std::optional<std::string>(std::span<const ProbeState>, double)> stop_after_step{};
  std::optional<std::string> stopped{};
};

/// The probes' points now and at the start, for RunOptions::stop_after_step.
template <int Dim> std::vector<ProbeState> probe_states(const Scene<Dim>& scene) {
  std::vector<ProbeState> out;
  for (std::size_t k = 0; k < scene.probe_particles.size(); ++k) {
    const auto p = static_cast<std::size_t>(scene.probe_particles[k]);
    out.push_back({scene.probe_names[k], padded<Dim>(scene.particles.x0[p]),
                   padded<Dim>(scene.particles.x[p])});
  }
  return out;
}

/// Asks RunOptions::stop_after_step, if the run has one, after a completed step.
template <int Dim> void ask_stop(LoopState& s, const Scene<Dim>& scene, double time) {
  if (s.stop_after_step)
    s.stopped = s.stop_after_step(probe_states(scene), time);
}

void check_limits(const TimeSpec& time, const LoopState& s) {
  if (s.step - s.stage_first_step >= time.max_steps)
    throw NumericalError(fmt::format("reached max_steps = {} at t = {:g} before end_time = "
                                     "{:g}; raise time.max_steps or the time step",
                                     time.max_steps, s.t, time.end_time));
}

// Time steps shorter than this fraction of the nominal step are absorbed into the previous
// one, so round-off never produces a sliver step at an output time or the end.
constexpr double kSliver = 1e-9;

/// The strength of the frictional materials during a stage: c / F, tan(phi) / F with F moving
/// from the previous stage's factor to the stage's own over a quasi-static stage, or set at
/// the start of a dynamic one. The materials keep their history; only the return map changes.
template <int Dim> class StageStrength {
public:
  /// `applied`: the factor the materials have now (the previous stage's), kept up to date as
  /// the factor changes (the caller's record outlives a failed stage); `end`: the stage's.
  StageStrength(Scene<Dim>& scene, const CaseSpec& case_spec, double& applied, double end)
      : scene_(scene), case_spec_(case_spec), start_(applied), end_(end), applied_(applied) {}

  /// Sets the factor for a step that ends at the fraction `progress` of the stage.
  void at(double progress) {
    const double factor = scene_.spec.analysis == AnalysisType::ImplicitQuasistatic
                              ? start_ + (end_ - start_) * progress
                              : end_;
    if (factor == applied_)
      return;
    for (std::size_t m = 0; m < scene_.materials.size(); ++m)
      if (auto* plastic = dynamic_cast<PlasticMaterial*>(scene_.materials[m].get()))
        plastic->replace_model(
            make_plastic_model(reduce_strength(case_spec_.materials[m], factor)));
    applied_ = factor;
  }
  double factor() const { return applied_; }

private:
  Scene<Dim>& scene_;
  const CaseSpec& case_spec_; ///< the case as written, full strength
  double start_, end_;
  double& applied_; ///< the factor the materials' return maps have
};

/// Splits the points that meet their body's criterion after a completed step (a converged one
/// in the implicit analyses), so every step starts from a consistent set of points.
template <int Dim, class Solver>
void split_after_step(Scene<Dim>& scene, Solver& solver, RunResult& result) {
  const Index splits = split_material_points(scene);
  if (splits == 0)
    return;
  solver.particles_changed();
  result.extra["splits"] += static_cast<double>(splits);
}

/// Writes A in Matrix Market coordinate format (both triangles, 1-based).
void write_matrix_market(const fs::path& file, const SparseMatrix& A) {
  std::ofstream out(file);
  out << "%%MatrixMarket matrix coordinate real general\n"
      << A.rows() << ' ' << A.cols() << ' ' << A.nonZeros() << '\n';
  out.precision(17);
  for (Eigen::Index c = 0; c < A.outerSize(); ++c)
    for (SparseMatrix::InnerIterator it(A, c); it; ++it)
      out << it.row() + 1 << ' ' << c + 1 << ' ' << it.value() << '\n';
  if (!out)
    throw std::runtime_error("cannot write " + file.string());
}

/// Explicit dynamics: CFL or fixed steps until end_time.
template <int Dim>
void run_explicit(Scene<Dim>& scene, Recorder<Dim>& rec, LoopState& s, RunResult& result,
                  StageWatch& watch) {
  auto solver = make_explicit_solver(scene);
  const TimeSpec& time = scene.spec.time;
  if (s.step == 0)
    rec.append_row(solver->energies(), solver->reactions(), {}, 0, 0, 0);
  // The stepping loop's own time (summary.json "seconds_stepping"): throughput figures leave
  // out building the scene and writing results.
  const auto loop_start = std::chrono::steady_clock::now();
  const double frame_seconds_before = rec.frame_seconds;
  const Index steps_before = s.step;
  const auto record_loop_time = [&] {
    result.extra["seconds_stepping"] +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - loop_start).count() -
        (rec.frame_seconds - frame_seconds_before);
    result.extra["steps_stepping"] += static_cast<double>(s.step - steps_before);
  };
  while (s.t < time.end_time * (1.0 - 1e-14)) {
    check_limits(time, s);
    if (g_interrupted) {
      record_loop_time();
      return;
    }
    double dt = time.dt ? *time.dt : solver->stable_dt(*time.cfl);
    if (!(dt > 0) || !std::isfinite(dt))
      throw NumericalError(fmt::format("time step became {:g}", dt));
    const double target = rec.target(time.end_time);
    if (s.t + dt * (1.0 + kSliver) >= target)
      dt = target - s.t;
    const double t_end = (s.t + dt >= target) ? target : s.t + dt;
    // Above the Courant limit the step would amplify every mode: stop before taking it, with
    // the state, still good, as the last frame.
    if (time.dt)
      if (auto violation = find_courant_violation(scene, dt)) {
        rec.final_frame(s.step, s.t);
        rec.stop_if_violated(violation, fmt::format("before the step from t = {:g}", s.t));
      }
    const std::string at_end = fmt::format("at the end of the step (t = {:g})", t_end);
    auto guard = [&] {
      rec.stop_if_violated(solver->grid_violation(), at_end);
      rec.stop_if_violated(find_particle_violation(scene.particles), at_end);
    };
    watch.before_step(scene.particles);
    try {
      solver->step(dt);
    } catch (const NumericalError&) {
      // A material that met det F <= 0 or a point that left the grid: name the point if the
      // state shows it, otherwise pass the solver's own message on.
      guard();
      throw;
    }
    guard();
    s.t = t_end;
    ++s.step;
    const bool stage_ends = watch.ends_after_step(scene.particles, s.t, dt);
    ask_stop(s, scene, rec.stage_start_time + s.t);
    split_after_step(scene, *solver, result);
    const Energies e = solver->energies();
    if (!std::isfinite(e.kinetic) || !std::isfinite(e.strain))
      throw NumericalError("non-finite energy");
    rec.after_step(s.step, s.t, dt, e, solver->reactions(), {}, {});
    if (stage_ends || s.stopped)
      break;
  }
  record_loop_time();
  rec.final_frame(s.step, s.t);
  result.extra["active_nodes_last_step"] = static_cast<double>(solver->active_nodes());
}

/// Implicit analyses: steps cut back (halved) when Newton fails and
/// grown back (doubled, up to the initial step) after two easy steps. Each step's Newton
/// residual history goes to newton.log. A failure at the minimum step ends the run after
/// writing the last converged state as a frame. `loads_ramp`: the quasi-static loads follow
/// the stage's pseudo-time (the first stage); otherwise they act in full.
template <int Dim>
void run_implicit(Scene<Dim>& scene, Recorder<Dim>& rec, LoopState& s, RunResult& result,
                  const fs::path& out_dir, StageWatch& watch, StageStrength<Dim>& strength,
                  bool loads_ramp, const fs::path& dump_tangent) {
  auto solver = make_implicit_solver(scene, loads_ramp ? 0.0 : 1.0);
  result.linear_solver = solver->linear_solver();
  const TimeSpec& time = scene.spec.time;
  const double dt0 = *time.dt;
  const double min_dt = time.min_dt.value_or(dt0 / 1024.0);
  double dt = dt0;
  int easy_steps = 0;
  // One log for the run: the first stage creates it, later stages append.
  std::FILE* log = std::fopen((out_dir / "newton.log").c_str(), s.step == 0 ? "w" : "a");
  if (!log)
    throw std::runtime_error("cannot create " + (out_dir / "newton.log").string());
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> log_guard(log, std::fclose);
  if (s.step == 0)
    std::fprintf(log, "# step t_end dt converged iterations | max|R|/scale at each iterate\n");
  if (!scene.spec.stages.empty())
    std::fprintf(log, "# stage %zu '%s' from t = %.10g\n", rec.stage + 1,
                 scene.spec.stages[rec.stage].name.c_str(), rec.stage_start_time);
  Index newton_iterations = 0, linear_solves = 0, linear_iterations = 0, cutbacks = 0,
        max_iterations = 0;
  if (s.step == 0)
    rec.append_row(solver->energies(), solver->reactions(), solver->prescribed_reactions(), 0, 0,
                   0);
  auto record_totals = [&] {
    auto& x = result.extra;
    x["load_steps"] += static_cast<double>(s.step - s.stage_first_step);
    x["newton_iterations"] += static_cast<double>(newton_iterations);
    x["newton_iterations_max_per_step"] =
        std::max(x["newton_iterations_max_per_step"], static_cast<double>(max_iterations));
    x["linear_solves"] += static_cast<double>(linear_solves);
    x["linear_iterations"] += static_cast<double>(linear_iterations);
    x["cutbacks"] += static_cast<double>(cutbacks);
    const ImplicitTimings t = solver->timings();
    for (const auto& [key, seconds] : implicit_phases(t))
      x[key] += seconds;
    x["unknowns_last_step"] = static_cast<double>(solver->unknowns());
    if (!dump_tangent.empty())
      write_matrix_market(dump_tangent, solver->last_tangent());
  };
  try {
    while (s.t < time.end_time * (1.0 - 1e-14)) {
      check_limits(time, s);
      if (g_interrupted)
        break;
      const double target = rec.target(time.end_time);
      double step_dt = std::min(dt, target - s.t);
      if (s.t + step_dt * (1.0 + kSliver) >= target)
        step_dt = target - s.t;
      const double t_end = (s.t + step_dt >= target) ? target : s.t + step_dt;
      // Quasi-static loads ramp with the first stage's pseudo-time; dynamic loads act in full
      // from t = 0, and after the first stage every load does.
      const bool dynamic = scene.spec.analysis == AnalysisType::ImplicitDynamic;
      const double ramp = loads_ramp ? t_end / time.end_time : 1.0;
      strength.at(t_end / time.end_time);
      watch.before_step(scene.particles);
      const NewtonReport r = solver->step(dynamic ? 1.0 : ramp, ramp, step_dt);
      newton_iterations += r.iterations;
      linear_solves += r.linear_solves;
      linear_iterations += r.linear_iterations;
      std::fprintf(log, "%lld %.10g %.6g %s %d |", static_cast<long long>(s.step + 1),
                   rec.stage_start_time + t_end, step_dt, r.converged ? "yes" : "no", r.iterations);
      if (!r.abandoned_history.empty()) {
        std::fprintf(log, " [%s:", r.abandoned_line_search ? "line search" : "plain Newton");
        for (double v : r.abandoned_history)
          std::fprintf(log, " %.3e", v);
        std::fprintf(log, "; %s:]", r.abandoned_line_search ? "plain Newton" : "line search");
      }
      for (double v : r.residual_history)
        std::fprintf(log, " %.3e", v);
      std::fprintf(log, "%s%s\n", r.converged ? "" : "  ", r.message.c_str());
      std::fflush(log);
      if (!r.converged) {
        ++cutbacks;
        easy_steps = 0;
        if (step_dt <= min_dt * (1.0 + 1e-12))
          throw NumericalError(fmt::format(
              "Newton did not converge at the minimum load step dt = {:g} (t = {:g} -> {:g}{}): "
              "{}",
              step_dt, s.t, t_end,
              strength.factor() != 1.0 ? fmt::format(", strength factor {:.6g}", strength.factor())
                                       : "",
              r.message));
        dt = std::max(0.5 * step_dt, min_dt);
        continue;
      }
      rec.stop_if_violated(find_particle_violation(scene.particles),
                           fmt::format("after the converged step to t = {:g}", t_end));
      max_iterations = std::max<Index>(max_iterations, r.iterations);
      s.t = t_end;
      ++s.step;
      const bool stage_ends = watch.ends_after_step(scene.particles, s.t, step_dt);
      ask_stop(s, scene, rec.stage_start_time + s.t);
      split_after_step(scene, *solver, result);
      const int easy = scene.spec.solver.easy_newton_iterations;
      if (r.iterations <= easy && ++easy_steps >= 2) {
        dt = std::min(2.0 * dt, dt0);
        easy_steps = 0;
      } else if (r.iterations > easy) {
        easy_steps = 0;
      }
      rec.after_step(s.step, s.t, step_dt, solver->energies(), solver->reactions(),
                     solver->prescribed_reactions(), fmt::format("newton {}", r.iterations));
      if (stage_ends || s.stopped)
        break;
    }
  } catch (const StateGuardError&) {
    record_totals();
    throw;
  } catch (const NumericalError&) {
    record_totals();
    rec.final_frame(s.step, s.t); // the last converged state
    throw;
  }
  record_totals();
  rec.final_frame(s.step, s.t);
}

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

namespace {

/// run_case for a case of dimension Dim: the stages, each from the state the previous left.
template <int Dim> RunResult run_case_in(const CaseSpec& spec, const RunOptions& options) {
  const auto wall_start = std::chrono::steady_clock::now();
  // Everything that can reject the input happens before the first byte is written.
  Scene<Dim> scene = build_scene<Dim>(spec);
  RunResult result;
  result.out_dir = options.out_dir.empty() ? fs::path("results") / spec.name : options.out_dir;
  prepare_output_directory(result.out_dir, options.force);
  if (options.threads > 0)
    omp_set_num_threads(options.threads);

  fs::create_directories(result.out_dir);
  ResultsWriter writer(result.out_dir, run_detail::metadata_of(scene));
  TimeSeriesWriter series(result.out_dir / "timeseries.csv", run_detail::timeseries_columns(scene));

  const OutputSpec& out = spec.output;
  g_interrupted = false;
  auto previous_sigint = std::signal(SIGINT, on_interrupt);
  auto previous_sigterm = std::signal(SIGTERM, on_interrupt);

  const std::vector<StageSpec> stages = stages_of(spec);
  const bool staged = !spec.stages.empty();
  Recorder<Dim> recorder{scene, writer, series};
  LoopState state;
  state.stop_after_step = options.stop_after_step;
  result.status = "completed";
  result.particles = scene.particles.size();
  if (splitting_requested(spec)) {
    result.extra["particles_initial"] = static_cast<double>(scene.particles.size());
    result.extra["splits"] = 0.0;
  }
  recorder.write_frame(0, 0.0);
  double stage_start_time = 0;
  double strength_factor = 1.0;
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
  try {
    for (std::size_t k = 0; k < stages.size() && !g_interrupted; ++k) {
      const StageSpec& stage = stages[k];
      if (k > 0 && stages[k - 1].analysis == AnalysisType::ImplicitQuasistatic &&
          stage.analysis != AnalysisType::ImplicitQuasistatic)
        start_at_rest(scene.particles);
      scene.spec.analysis = stage.analysis;
      scene.spec.time = stage.time;
      state.t = 0;
      state.stage_first_step = state.step;
      stage_started = std::chrono::steady_clock::now();
      current = StageSummary{};
      current->name = stage.name;
      current->analysis = analysis_name(stage.analysis);
      current->start_time = stage_start_time;
      Progress progress(staged ? fmt::format("{} [{}]", spec.name, stage.name) : spec.name,
                        stage.time.end_time, options.progress);
      recorder.begin_stage(k, progress,
                           out.every_time ? *out.every_time
                                          : (out.every_steps ? 0.0 : stage.time.end_time / 20.0),
                           stage_start_time);
      StageWatch watch(stage);
      StageStrength<Dim> strength(scene, spec, strength_factor,
                                  stage.strength_factor.value_or(strength_factor));
      // From here on strength_factor follows the factor the materials have.
      if (stage.analysis == AnalysisType::Explicit) {
        strength.at(1.0);
        run_explicit(scene, recorder, state, result, watch);
      } else {
        run_implicit(scene, recorder, state, result, result.out_dir, watch, strength, k == 0,
                     options.dump_tangent);
      }
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
    }
    if (g_interrupted) {
      result.status = "interrupted";
      result.message =
          fmt::format("interrupted at step {}, t = {:g}", state.step, stage_start_time + state.t);
      result.exit_code = kExitOther;
    }
  } catch (const NumericalError& err) {
    result.status = "numerical_failure";
    result.message =
        fmt::format("step {}, t = {:g}{}: {}", state.step + 1, stage_start_time + state.t,
                    staged ? fmt::format(" (stage '{}')", current->name) : "", err.what());
    result.exit_code = kExitNumerical;
    if (current)
      end_stage(fmt::format("failed: {}", err.what()), stage_started);
    stage_start_time += state.t;
    state.t = 0;
  }
  if (out.stress_recovery || out.voxels)
    result.extra["seconds_post_processing"] = recorder.post_seconds;
  // With splitting, `particles` is the count at the end (particles_initial the one at t = 0).
  result.particles = scene.particles.size();
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
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  account_for_wall_time(result, recorder.frame_seconds);
  Progress(spec.name, 0, options.progress)
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
  write_summary_json(result.out_dir / "summary.json", summary);
  return result;
}

} // namespace

RunResult run_case(const CaseSpec& spec, const RunOptions& options) {
  return spec.dimension == 3 ? run_case_in<3>(spec, options) : run_case_in<2>(spec, options);
}

} // namespace talus
