#include "talus/solver/run.hpp"

#include "talus/core/errors.hpp"
#include "talus/core/scene.hpp"
#include "talus/io/progress.hpp"
#include "talus/io/results.hpp"
#include "talus/solver/explicit_solver.hpp"

#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <fmt/format.h>
#include <omp.h>

namespace talus {

namespace fs = std::filesystem;

namespace {

std::atomic<bool> g_interrupted{false};
extern "C" void on_interrupt(int) {
  g_interrupted = true;
}

// Result files a run owns; --force replaces exactly these and leaves anything else alone.
const char* const kResultFiles[] = {"run.h5", "run.xmf", "timeseries.csv", "summary.json"};

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
  std::vector<std::string> cols = {"time",           "step",          "dt",
                                   "kinetic_energy", "strain_energy", "gravity_energy",
                                   "total_energy",   "momentum_x",    "momentum_y"};
  for (int f = 0; f < kFaceCount; ++f)
    if (face_constrained(scene.spec.boundaries, f)) {
      cols.push_back(fmt::format("reaction_{}_x", face_name(f)));
      cols.push_back(fmt::format("reaction_{}_y", face_name(f)));
    }
  for (const auto& name : scene.probe_names)
    for (const char* q : {"x", "y", "vx", "vy", "sxx", "syy", "sxy", "szz"})
      cols.push_back(fmt::format("{}.{}", name, q));
  return cols;
}

std::vector<double> timeseries_row(const Scene<2>& scene, const ExplicitSolver& solver, double time,
                                   Index step, double dt) {
  const Energies e = solver.energies();
  std::vector<double> row = {time,
                             static_cast<double>(step),
                             dt,
                             e.kinetic,
                             e.strain,
                             e.gravity,
                             e.kinetic + e.strain + e.gravity,
                             e.momentum.x(),
                             e.momentum.y()};
  const auto reactions = solver.reactions();
  for (int f = 0; f < kFaceCount; ++f)
    if (face_constrained(scene.spec.boundaries, f)) {
      row.push_back(reactions[static_cast<std::size_t>(f)].x());
      row.push_back(reactions[static_cast<std::size_t>(f)].y());
    }
  const auto& P = scene.particles;
  for (const Index p : scene.probe_particles) {
    const auto s = static_cast<std::size_t>(p);
    row.insert(row.end(), {P.x[s].x(), P.x[s].y(), P.v[s].x(), P.v[s].y(), P.stress[s](0, 0),
                           P.stress[s](1, 1), P.stress[s](0, 1), P.stress[s](2, 2)});
  }
  return row;
}

} // namespace

void prepare_output_directory(const fs::path& dir, bool force) {
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
  for (const char* name : kResultFiles)
    fs::remove(dir / name, ec);
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

  auto solver = make_explicit_solver(scene);
  fs::create_directories(result.out_dir);
  ResultsWriter writer(result.out_dir, metadata_of(scene));
  TimeSeriesWriter series(result.out_dir / "timeseries.csv", timeseries_columns(scene));

  const TimeSpec& time = spec.time;
  const OutputSpec& out = spec.output;
  const double frame_interval =
      out.every_time ? *out.every_time : (out.every_steps ? 0.0 : time.end_time / 20.0);
  double next_frame_time = frame_interval;

  g_interrupted = false;
  auto previous_sigint = std::signal(SIGINT, on_interrupt);
  auto previous_sigterm = std::signal(SIGTERM, on_interrupt);

  Progress progress(spec.name, time.end_time, options.progress);
  double t = 0;
  Index step = 0;
  double dt = 0;
  result.status = "completed";
  result.particles = scene.particles.size();
  writer.write_frame(0, 0.0, scene.particles, out.fields);
  series.append(timeseries_row(scene, *solver, t, step, 0.0));
  bool frame_at_current_step = true;
  // Time steps shorter than this fraction of the nominal step are absorbed into the previous
  // one, so round-off never produces a sliver step at an output time or the end.
  constexpr double kSliver = 1e-9;
  try {
    while (t < time.end_time * (1.0 - 1e-14)) {
      if (step >= time.max_steps)
        throw NumericalError(fmt::format("reached max_steps = {} at t = {:g} before end_time = "
                                         "{:g}; raise time.max_steps or the time step",
                                         time.max_steps, t, time.end_time));
      if (g_interrupted) {
        result.status = "interrupted";
        result.message = fmt::format("interrupted at step {}, t = {:g}", step, t);
        result.exit_code = kExitOther;
        break;
      }
      dt = time.dt ? *time.dt : solver->stable_dt(*time.cfl);
      if (!(dt > 0) || !std::isfinite(dt))
        throw NumericalError(
            fmt::format("time step became {:g} at step {}, t = {:g}", dt, step, t));
      double target = time.end_time;
      if (frame_interval > 0)
        target = std::min(target, next_frame_time);
      if (t + dt * (1.0 + kSliver) >= target)
        dt = target - t;
      solver->step(dt);
      t = (t + dt >= target) ? target : t + dt;
      ++step;
      series.append(timeseries_row(scene, *solver, t, step, dt));
      const Energies e = solver->energies();
      if (!std::isfinite(e.kinetic) || !std::isfinite(e.strain))
        throw NumericalError(fmt::format("non-finite energy at step {}, t = {:g}", step, t));
      frame_at_current_step = false;
      const bool frame_due =
          out.every_steps ? (step % *out.every_steps == 0) : (t >= next_frame_time * (1.0 - 1e-12));
      if (frame_due) {
        writer.write_frame(step, t, scene.particles, out.fields);
        frame_at_current_step = true;
        while (frame_interval > 0 && next_frame_time <= t * (1.0 + 1e-12))
          next_frame_time += frame_interval;
      }
      progress.update(step, t, dt);
    }
    if (!frame_at_current_step)
      writer.write_frame(step, t, scene.particles, out.fields);
  } catch (const NumericalError& err) {
    result.status = "numerical_failure";
    result.message = fmt::format("step {}, t = {:g}: {}", step + 1, t, err.what());
    result.exit_code = kExitNumerical;
  }
  std::signal(SIGINT, previous_sigint);
  std::signal(SIGTERM, previous_sigterm);

  result.steps = step;
  result.final_time = t;
  result.frames = writer.frames_written();
  result.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  progress.finish(result.status == "completed"
                      ? fmt::format("done: {} steps, {} frames, {:.2f} s", step, result.frames,
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
  summary.extra["active_nodes_last_step"] = static_cast<double>(solver->active_nodes());
  write_summary_json(result.out_dir / "summary.json", summary);
  return result;
}

} // namespace talus
