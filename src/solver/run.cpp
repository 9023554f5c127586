#include "talus/solver/run.hpp"

#include "talus/core/errors.hpp"
#include "talus/core/scene.hpp"
#include "talus/core/splitting.hpp"
#include "talus/io/progress.hpp"
#include "talus/io/results.hpp"
#include "talus/post/stress_recovery.hpp"
#include "talus/post/voxels.hpp"
#include "talus/solver/explicit_solver.hpp"
#include "talus/solver/implicit_solver.hpp"
#include "talus/solver/state_guard.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <fmt/format.h>
#include <omp.h>
#include <optional>

namespace talus {

namespace fs = std::filesystem;

namespace {

std::atomic<bool> g_interrupted{false};
extern "C" void on_interrupt(int) {
  g_interrupted = true;
}

// Result files a run owns; --force replaces exactly these and leaves anything else alone.
const char* const kResultFiles[] = {"run.h5", "run.xmf", "timeseries.csv", "summary.json",
                                    "newton.log"};

RunMetadata metadata_of(const Scene<2>& scene) {
  const CaseSpec& spec = scene.spec;
  RunMetadata m;
  m.case_name = spec.name;
  m.case_file = spec.source_file;
  m.case_text = spec.source_text;
  m.overrides = spec.overrides;
  m.version = TALUS_VERSION;
  m.dimension = spec.dimension;
  m.grid_origin = spec.grid.origin;
  m.grid_extent = spec.grid.extent;
  m.cell_size = spec.grid.cell_size;
  for (const auto& mat : spec.materials)
    m.material_names.push_back(mat.name);
  for (const auto& b : spec.bodies)
    m.body_names.push_back(b.name);
  return m;
}

bool face_constrained(const BoundarySpec& bc, int face) {
  const FaceCondition c[kFaceCount] = {bc.x_min, bc.x_max, bc.y_min, bc.y_max};
  return c[face] != FaceCondition::Free;
}

std::vector<std::string> timeseries_columns(const Scene<2>& scene) {
  std::vector<std::string> cols = {
      "time",           "step",         "dt",         "kinetic_energy", "strain_energy",
      "gravity_energy", "total_energy", "momentum_x", "momentum_y",     "particles"};
  for (int f = 0; f < kFaceCount; ++f)
    if (face_constrained(scene.spec.boundaries, f)) {
      cols.push_back(fmt::format("reaction_{}_x", face_name(f)));
      cols.push_back(fmt::format("reaction_{}_y", face_name(f)));
    }
  for (const auto& region : scene.spec.prescribed) {
    cols.push_back(fmt::format("reaction_{}_x", region.name));
    cols.push_back(fmt::format("reaction_{}_y", region.name));
  }
  for (const auto& name : scene.probe_names)
    for (const char* q : {"x", "y", "vx", "vy", "sxx", "syy", "sxy", "szz"})
      cols.push_back(fmt::format("{}.{}", name, q));
  return cols;
}

std::vector<double> timeseries_row(const Scene<2>& scene, const Energies& e,
                                   const std::array<Vec2, kFaceCount>& reactions,
                                   const std::vector<Vec2>& prescribed, double time, Index step,
                                   double dt) {
  std::vector<double> row = {time,
                             static_cast<double>(step),
                             dt,
                             e.kinetic,
                             e.strain,
                             e.gravity,
                             e.kinetic + e.strain + e.gravity,
                             e.momentum.x(),
                             e.momentum.y(),
                             static_cast<double>(scene.particles.size())};
  for (int f = 0; f < kFaceCount; ++f)
    if (face_constrained(scene.spec.boundaries, f)) {
      row.push_back(reactions[static_cast<std::size_t>(f)].x());
      row.push_back(reactions[static_cast<std::size_t>(f)].y());
    }
  for (std::size_t r = 0; r < scene.spec.prescribed.size(); ++r) {
    const Vec2 f = r < prescribed.size() ? prescribed[r] : Vec2::Zero();
    row.push_back(f.x());
    row.push_back(f.y());
  }
  const auto& P = scene.particles;
  for (const Index p : scene.probe_particles) {
    const auto s = static_cast<std::size_t>(p);
    row.insert(row.end(), {P.x[s].x(), P.x[s].y(), P.v[s].x(), P.v[s].y(), P.stress[s](0, 0),
                           P.stress[s](1, 1), P.stress[s](0, 1), P.stress[s](2, 2)});
  }
  return row;
}

// What both analyses share while stepping: frames on the output schedule, time-series rows,
// progress, and the interrupt flag.
struct Recorder {
  const Scene<2>& scene;
  ResultsWriter& writer;
  TimeSeriesWriter& series;
  Progress& progress;
  double frame_interval;
  double next_frame_time;
  bool frame_at_current_step = true;
  Index last_frame_step = 0;
  double last_frame_time = 0;
  double post_seconds = 0; ///< stress recovery and voxels, the frames' post-processing
  std::optional<StressRecovery> recovery{}; ///< made on the first frame, reused by the others
  Voxels voxels{};
  std::vector<double> plastic_strain{}; ///< gathered from the materials' history per frame

  /// Writes the current state as a frame, with the post-processing fields the case asks for:
  /// they are computed here, on output frames only.
  void write_frame(Index step, double t) {
    const OutputSpec& out = scene.spec.output;
    const auto start = std::chrono::steady_clock::now();
    FramePost post;
    if (out.stress_recovery) {
      if (!recovery)
        recovery.emplace(scene.grid, scene.spec.solver.shape);
      post.stress = &recovery->recover(scene.particles);
    }
    if (out.voxels) {
      update_voxels(scene.particles, scene.grid.origin(),
                    out.pattern_size.value_or(scene.grid.cell_size()), voxels);
      post.voxels = &voxels;
    }
    post_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (std::find(out.fields.begin(), out.fields.end(), OutputField::PlasticStrain) !=
        out.fields.end()) {
      plastic_strain.assign(static_cast<std::size_t>(scene.particles.size()), 0.0);
      for (std::size_t m = 0; m < scene.materials.size(); ++m)
        scene.materials[m]->plastic_strain(scene.particles_of_material[m], plastic_strain);
      post.plastic_strain = &plastic_strain;
    }
    writer.write_frame(step, t, scene.particles, out.fields, post);
    frame_at_current_step = true;
    last_frame_step = step;
    last_frame_time = t;
  }

  /// Stops the run (StateGuardError) when the guard found something; `when` says at which
  /// point of the step. A bad state is not written: the frames already on disk are the good ones.
  void stop_if_violated(const std::optional<StateViolation>& violation,
                        const std::string& when) const {
    if (violation)
      throw StateGuardError(
          fmt::format("state guard: {} {}; the last good frame is frame {} (step {}, t = {:g})",
                      violation->describe(), when, writer.frames_written() - 1, last_frame_step,
                      last_frame_time));
  }

  /// The end of the next step: the end time or the next frame time, whichever comes first.
  double target(double end_time) const {
    return frame_interval > 0 ? std::min(end_time, next_frame_time) : end_time;
  }
  void after_step(Index step, double t, double dt, const Energies& e,
                  const std::array<Vec2, kFaceCount>& reactions,
                  const std::vector<Vec2>& prescribed, const std::string& extra) {
    series.append(timeseries_row(scene, e, reactions, prescribed, t, step, dt));
    const OutputSpec& out = scene.spec.output;
    frame_at_current_step = false;
    const bool due =
        out.every_steps ? (step % *out.every_steps == 0) : (t >= next_frame_time * (1.0 - 1e-12));
    if (due) {
      write_frame(step, t);
      while (frame_interval > 0 && next_frame_time <= t * (1.0 + 1e-12))
        next_frame_time += frame_interval;
    }
    progress.update(step, t, dt, extra);
  }
  /// Makes sure the state the run ends in is a frame.
  void final_frame(Index step, double t) {
    if (!frame_at_current_step)
      write_frame(step, t);
  }
};

struct LoopState {
  double t = 0;
  Index step = 0;
};

void check_limits(const TimeSpec& time, const LoopState& s) {
  if (s.step >= time.max_steps)
    throw NumericalError(fmt::format("reached max_steps = {} at t = {:g} before end_time = "
                                     "{:g}; raise time.max_steps or the time step",
                                     time.max_steps, s.t, time.end_time));
}

// Time steps shorter than this fraction of the nominal step are absorbed into the previous
// one, so round-off never produces a sliver step at an output time or the end.
constexpr double kSliver = 1e-9;

/// Splits the points that meet their body's criterion after a completed step (a converged one
/// in the implicit analyses), so every step starts from a consistent set of points.
template <class Solver> void split_after_step(Scene<2>& scene, Solver& solver, RunResult& result) {
  const Index splits = split_material_points(scene);
  if (splits == 0)
    return;
  solver.particles_changed();
  result.extra["splits"] += static_cast<double>(splits);
}

/// Explicit dynamics: CFL or fixed steps until end_time.
void run_explicit(Scene<2>& scene, Recorder& rec, LoopState& s, RunResult& result) {
  auto solver = make_explicit_solver(scene);
  const TimeSpec& time = scene.spec.time;
  rec.series.append(timeseries_row(scene, solver->energies(), solver->reactions(), {}, 0, 0, 0));
  while (s.t < time.end_time * (1.0 - 1e-14)) {
    check_limits(time, s);
    if (g_interrupted)
      return;
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
    split_after_step(scene, *solver, result);
    const Energies e = solver->energies();
    if (!std::isfinite(e.kinetic) || !std::isfinite(e.strain))
      throw NumericalError("non-finite energy");
    rec.after_step(s.step, s.t, dt, e, solver->reactions(), {}, {});
  }
  rec.final_frame(s.step, s.t);
  result.extra["active_nodes_last_step"] = static_cast<double>(solver->active_nodes());
}

/// Implicit analyses: steps cut back (halved) when Newton fails and
/// grown back (doubled, up to the initial step) after two easy steps. Each step's Newton
/// residual history goes to newton.log. A failure at the minimum step ends the run after
/// writing the last converged state as a frame.
void run_implicit(Scene<2>& scene, Recorder& rec, LoopState& s, RunResult& result,
                  const fs::path& out_dir) {
  auto solver = make_implicit_solver(scene);
  result.linear_solver = solver->linear_solver();
  const TimeSpec& time = scene.spec.time;
  const double dt0 = *time.dt;
  const double min_dt = time.min_dt.value_or(dt0 / 1024.0);
  double dt = dt0;
  int easy_steps = 0;
  std::FILE* log = std::fopen((out_dir / "newton.log").c_str(), "w");
  if (!log)
    throw std::runtime_error("cannot create " + (out_dir / "newton.log").string());
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> log_guard(log, std::fclose);
  std::fprintf(log, "# step t_end dt converged iterations | max|R|/scale at each iterate\n");
  double assembly = 0, factorization = 0, solve = 0;
  Index newton_iterations = 0, linear_solves = 0, cutbacks = 0, max_iterations = 0;
  rec.series.append(timeseries_row(scene, solver->energies(), solver->reactions(),
                                   solver->prescribed_reactions(), 0, 0, 0));
  auto record_totals = [&] {
    result.extra["load_steps"] = static_cast<double>(s.step);
    result.extra["newton_iterations"] = static_cast<double>(newton_iterations);
    result.extra["newton_iterations_max_per_step"] = static_cast<double>(max_iterations);
    result.extra["linear_solves"] = static_cast<double>(linear_solves);
    result.extra["cutbacks"] = static_cast<double>(cutbacks);
    result.extra["seconds_assembly"] = assembly;
    result.extra["seconds_factorization"] = factorization;
    result.extra["seconds_solve"] = solve;
    result.extra["seconds_particle_update"] = solver->seconds_particle_update();
    result.extra["unknowns_last_step"] = static_cast<double>(solver->unknowns());
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
      // Quasi-static loads ramp with the pseudo-time; dynamic loads act in full from t = 0.
      const double load_factor =
          scene.spec.analysis == AnalysisType::ImplicitDynamic ? 1.0 : t_end / time.end_time;
      const NewtonReport r = solver->step(load_factor, t_end / time.end_time, step_dt);
      assembly += r.seconds_assembly;
      factorization += r.seconds_factorization;
      solve += r.seconds_solve;
      newton_iterations += r.iterations;
      linear_solves += r.linear_solves;
      std::fprintf(log, "%lld %.10g %.6g %s %d |", static_cast<long long>(s.step + 1), t_end,
                   step_dt, r.converged ? "yes" : "no", r.iterations);
      if (!r.abandoned_history.empty()) {
        std::fprintf(log, " [plain Newton:");
        for (double v : r.abandoned_history)
          std::fprintf(log, " %.3e", v);
        std::fprintf(log, "; line search:]");
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
              "Newton did not converge at the minimum load step dt = {:g} (t = {:g} -> {:g}): {}",
              step_dt, s.t, t_end, r.message));
        dt = std::max(0.5 * step_dt, min_dt);
        continue;
      }
      rec.stop_if_violated(find_particle_violation(scene.particles),
                           fmt::format("after the converged step to t = {:g}", t_end));
      max_iterations = std::max<Index>(max_iterations, r.iterations);
      s.t = t_end;
      ++s.step;
      split_after_step(scene, *solver, result);
      if (r.iterations <= 4 && ++easy_steps >= 2) {
        dt = std::min(2.0 * dt, dt0);
        easy_steps = 0;
      } else if (r.iterations > 4) {
        easy_steps = 0;
      }
      rec.after_step(s.step, s.t, step_dt, solver->energies(), solver->reactions(),
                     solver->prescribed_reactions(), fmt::format("newton {}", r.iterations));
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

RunResult run_case(const CaseSpec& spec, const RunOptions& options) {
  const auto wall_start = std::chrono::steady_clock::now();
  // Everything that can reject the input happens before the first byte is written.
  Scene<2> scene = build_scene(spec);
  RunResult result;
  result.out_dir = options.out_dir.empty() ? fs::path("results") / spec.name : options.out_dir;
  prepare_output_directory(result.out_dir, options.force);
  if (options.threads > 0)
    omp_set_num_threads(options.threads);

  fs::create_directories(result.out_dir);
  ResultsWriter writer(result.out_dir, metadata_of(scene));
  TimeSeriesWriter series(result.out_dir / "timeseries.csv", timeseries_columns(scene));

  const TimeSpec& time = spec.time;
  const OutputSpec& out = spec.output;
  const double frame_interval =
      out.every_time ? *out.every_time : (out.every_steps ? 0.0 : time.end_time / 20.0);

  g_interrupted = false;
  auto previous_sigint = std::signal(SIGINT, on_interrupt);
  auto previous_sigterm = std::signal(SIGTERM, on_interrupt);

  Progress progress(spec.name, time.end_time, options.progress);
  Recorder recorder{scene, writer, series, progress, frame_interval, frame_interval};
  LoopState state;
  result.status = "completed";
  result.particles = scene.particles.size();
  if (splitting_requested(spec)) {
    result.extra["particles_initial"] = static_cast<double>(scene.particles.size());
    result.extra["splits"] = 0.0;
  }
  recorder.write_frame(0, 0.0);
  try {
    if (spec.analysis == AnalysisType::Explicit)
      run_explicit(scene, recorder, state, result);
    else
      run_implicit(scene, recorder, state, result, result.out_dir);
    if (g_interrupted) {
      recorder.final_frame(state.step, state.t);
      result.status = "interrupted";
      result.message = fmt::format("interrupted at step {}, t = {:g}", state.step, state.t);
      result.exit_code = kExitOther;
    }
  } catch (const NumericalError& err) {
    result.status = "numerical_failure";
    result.message = fmt::format("step {}, t = {:g}: {}", state.step + 1, state.t, err.what());
    result.exit_code = kExitNumerical;
  }
  if (out.stress_recovery || out.voxels)
    result.extra["seconds_post_processing"] = recorder.post_seconds;
  // With splitting, `particles` is the count at the end (particles_initial the one at t = 0).
  result.particles = scene.particles.size();
  if (options.final_state)
    options.final_state(scene);
  std::signal(SIGINT, previous_sigint);
  std::signal(SIGTERM, previous_sigterm);

  result.steps = state.step;
  result.final_time = state.t;
  result.frames = writer.frames_written();
  result.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  progress.finish(result.status == "completed"
                      ? fmt::format("done: {} steps, {} frames, {:.2f} s", state.step,
                                    result.frames, result.wall_seconds)
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
  write_summary_json(result.out_dir / "summary.json", summary);
  return result;
}

} // namespace talus
