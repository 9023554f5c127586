#pragma once
// Internal to run_case (src/solver/run.cpp, case_run.hpp): what a run records while it steps. The
// frames on the output schedule, timeseries.csv rows, the progress line, and the state guard's
// stop. Times are the stage's own (from 0 at its start); frames and rows are written at the run's
// time, the stage's start time plus the stage's time.
#include "prescribed_columns.hpp"
#include "run_state.hpp"
#include "talus/io/progress.hpp"
#include "talus/io/results.hpp"
#include "talus/post/stress_recovery.hpp"
#include "talus/post/voxels.hpp"
#include "talus/scene/migration.hpp"
#include "talus/scene/scene.hpp"
#include "talus/solver/energies.hpp"
#include "talus/solver/state_guard.hpp"

#include <algorithm>
#include <chrono>
#include <fmt/format.h>
#include <optional>
#include <string>
#include <vector>

namespace talus::run_detail {

template <int Dim> RunMetadata metadata_of(const Scene<Dim>& scene) {
  const CaseSpec& spec = scene.spec;
  RunMetadata m;
  m.case_name = spec.name;
  m.case_file = spec.source_file;
  m.case_text = spec.source_text;
  m.overrides = spec.overrides;
  m.version = TALUS_VERSION;
  m.dimension = Dim;
  m.geometry = Dim == 3                                  ? "3d"
               : spec.geometry == Geometry::Axisymmetric ? "axisymmetric"
                                                         : "plane_strain";
  m.grid_origin = spec.grid.origin;
  m.grid_extent = spec.grid.extent;
  m.cell_size = spec.grid.cell_size;
  for (const auto& mat : spec.materials)
    m.material_names.push_back(mat.name);
  for (const auto& b : spec.bodies)
    m.body_names.push_back(b.name);
  return m;
}

/// Whether the face holds a component (a platen holds none: its load is the reaction).
inline bool face_constrained(const BoundarySpec& bc, int face) {
  return bc[face] == FaceCondition::Fixed || bc[face] == FaceCondition::Roller;
}

/// The components of a vector column: x, y (and z in 3D).
template <int Dim> std::vector<const char*> axes() {
  if constexpr (Dim == 3)
    return {"x", "y", "z"};
  else
    return {"x", "y"};
}

/// The stress components a probe records: the in-plane ones and zz (2D), all six (3D).
template <int Dim> std::vector<std::pair<int, int>> probe_stress_components() {
  if constexpr (Dim == 3)
    return {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {1, 2}, {0, 2}};
  else
    return {{0, 0}, {1, 1}, {0, 1}, {2, 2}};
}

/// `stiffness`: the run measures the current stiffness (RunOptions::measure_stiffness).
template <int Dim>
std::vector<std::string> timeseries_columns(const Scene<Dim>& scene, bool stiffness) {
  std::vector<std::string> cols = {
      "time", "step", "dt", "kinetic_energy", "strain_energy", "gravity_energy", "total_energy"};
  for (const char* a : axes<Dim>())
    cols.push_back(fmt::format("momentum_{}", a));
  cols.push_back("particles");
  if (!scene.spec.stages.empty())
    cols.push_back("stage"); // 1, 2, ... in the order of the case's stages
  for (int f = 0; f < face_count(Dim); ++f)
    if (face_constrained(scene.spec.boundaries, f))
      for (const char* a : axes<Dim>())
        cols.push_back(fmt::format("reaction_{}_{}", face_name(f), a));
  for (const auto& region : scene.spec.prescribed) {
    for (const char* a : axes<Dim>())
      cols.push_back(fmt::format("reaction_{}_{}", region.name, a));
    append_prescribed_columns(scene.spec, region, cols);
  }
  for (const auto& name : scene.probe_names) {
    for (const char* a : axes<Dim>())
      cols.push_back(fmt::format("{}.{}", name, a));
    for (const char* a : axes<Dim>())
      cols.push_back(fmt::format("{}.v{}", name, a));
    for (const auto& [i, j] : probe_stress_components<Dim>())
      cols.push_back(fmt::format("{}.s{}{}", name, "xyz"[i], "xyz"[j]));
  }
  if (stiffness)
    cols.push_back("current_stiffness");
  return cols;
}

/// A probe's point now: where it started and is, its velocity and stress.
struct ProbeReading {
  Vec3 x0 = Vec3::Zero(), x = Vec3::Zero(), v = Vec3::Zero();
  Mat3 stress = Mat3::Zero();
};

/// The probes' points, wherever they live: the rank that holds a point reads it and the others
/// add zeros. Collective.
template <int Dim> std::vector<ProbeReading> probe_readings(const Scene<Dim>& scene) {
  const auto& P = scene.particles;
  std::vector<ProbeReading> out(scene.probe_particles.size());
  for (std::size_t k = 0; k < out.size(); ++k)
    if (const Index p = scene.probe_particles[k]; p >= 0) {
      const auto s = static_cast<std::size_t>(p);
      out[k] = {padded<Dim>(P.x0[s]), padded<Dim>(P.x[s]), padded<Dim>(P.v[s]), P.stress[s]};
    }
  if (out.empty())
    return out;
  constexpr std::size_t kValues = 18;
  std::vector<double> flat(out.size() * kValues);
  for (std::size_t k = 0; k < out.size(); ++k) {
    double* f = flat.data() + k * kValues;
    std::copy_n(out[k].x0.data(), 3, f);
    std::copy_n(out[k].x.data(), 3, f + 3);
    std::copy_n(out[k].v.data(), 3, f + 6);
    std::copy_n(out[k].stress.data(), 9, f + 9);
  }
  flat = scene.decomposition->comm().sum(flat);
  for (std::size_t k = 0; k < out.size(); ++k) {
    const double* f = flat.data() + k * kValues;
    out[k] = {Vec3(f), Vec3(f + 3), Vec3(f + 6), Eigen::Map<const Mat3>(f + 9)};
  }
  return out;
}

/// The run's point count: the ranks' counts added. Collective.
template <int Dim> Index point_count(const Scene<Dim>& scene) {
  return scene.decomposition->comm().sum(std::int64_t{scene.particles.size()});
}

template <int Dim>
std::vector<double>
timeseries_row(const Scene<Dim>& scene, const Energies& e, const FaceReactions& reactions,
               const std::vector<Vec3>& prescribed, double prescribed_fraction, double time,
               Index step, double dt, std::size_t stage, const double* stiffness) {
  std::vector<double> row = {time,      static_cast<double>(step),       dt, e.kinetic, e.strain,
                             e.gravity, e.kinetic + e.strain + e.gravity};
  for (int d = 0; d < Dim; ++d)
    row.push_back(e.momentum[d]);
  row.push_back(static_cast<double>(point_count(scene)));
  if (!scene.spec.stages.empty())
    row.push_back(static_cast<double>(stage + 1));
  for (int f = 0; f < face_count(Dim); ++f)
    if (face_constrained(scene.spec.boundaries, f))
      for (int d = 0; d < Dim; ++d)
        row.push_back(reactions[static_cast<std::size_t>(f)][d]);
  for (std::size_t r = 0; r < scene.spec.prescribed.size(); ++r) {
    const Vec3 f = r < prescribed.size() ? prescribed[r] : Vec3::Zero();
    for (int d = 0; d < Dim; ++d)
      row.push_back(f[d]);
    append_prescribed_values(scene.spec, scene.spec.prescribed[r], prescribed_fraction, f, row);
  }
  for (const ProbeReading& probe : probe_readings(scene)) {
    for (int d = 0; d < Dim; ++d)
      row.push_back(probe.x[d]);
    for (int d = 0; d < Dim; ++d)
      row.push_back(probe.v[d]);
    for (const auto& [i, j] : probe_stress_components<Dim>())
      row.push_back(probe.stress(i, j));
  }
  if (stiffness)
    row.push_back(*stiffness);
  return row;
}

// What both analyses share while stepping: frames on the output schedule, time-series rows,
// progress, and the state guard's stop.
template <int Dim> struct Recorder : FrameSchedule {
  const Scene<Dim>& scene;
  ResultsWriter& writer;
  TimeSeriesWriter& series;
  Progress* progress = nullptr; ///< the current stage's progress line
  double frame_interval = 0;
  double stage_start_time = 0;
  std::size_t stage = 0;                         ///< index into the run's stages
  std::optional<StressRecovery<Dim>> recovery{}; ///< made on the first frame, reused after
  Voxels<Dim> voxels{};
  std::vector<double> plastic_strain{}; ///< gathered from the materials' history per frame
  /// The current stiffness of a run that measures it (the time series' last column), or null.
  const double* current_stiffness = nullptr;
  /// The fraction of their displacement the prescribed boxes have reached (implicit runs).
  double prescribed_fraction = 0;

  /// Writes the current state as a frame, with the post-processing fields the case asks for:
  /// they are computed here, on output frames only.
  void write_frame(Index step, double t) {
    const OutputSpec& out = scene.spec.output;
    const auto start = std::chrono::steady_clock::now();
    const bool plastic = std::find(out.fields.begin(), out.fields.end(),
                                   OutputField::PlasticStrain) != out.fields.end();
    // A distributed run writes its frames from rank 0, with every rank's points in the serial
    // order: the file is the one a serial run writes.
    Particles<Dim> gathered;
    if (scene.distributed()) {
      gathered = gather_points(scene, plastic ? &plastic_strain : nullptr);
      if (!scene.decomposition->comm().root()) {
        writer.skip_frame();
        note_frame(step, t, start);
        return;
      }
    } else if (plastic) {
      plastic_strain.assign(static_cast<std::size_t>(scene.particles.size()), 0.0);
      for (std::size_t m = 0; m < scene.materials.size(); ++m)
        scene.materials[m]->plastic_strain(scene.particles_of_material[m], plastic_strain);
    }
    const Particles<Dim>& points = scene.distributed() ? gathered : scene.particles;
    FramePost<Dim> post;
    if (out.stress_recovery) {
      if (!recovery)
        recovery.emplace(scene.grid, scene.spec.solver.shape);
      post.stress = &recovery->recover(points);
    }
    if (out.voxels) {
      update_voxels<Dim>(points, scene.grid.origin(),
                         out.pattern_size.value_or(scene.grid.cell_size()), voxels);
      post.voxels = &voxels;
    }
    post_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (plastic)
      post.plastic_strain = &plastic_strain;
    writer.write_frame<Dim>(step, stage_start_time + t, points, out.fields, post);
    note_frame(step, t, start);
  }

  void note_frame(Index step, double t, std::chrono::steady_clock::time_point start) {
    frame_seconds +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    frame_at_current_step = true;
    last_frame_step = step;
    last_frame_time = stage_start_time + t;
  }

  void begin_stage(std::size_t index, Progress& stage_progress, double interval,
                   double start_time) {
    stage = index;
    progress = &stage_progress;
    frame_interval = interval;
    next_frame_time = interval;
    stage_start_time = start_time;
  }

  /// The time-series row of the current state at the stage's time t.
  void append_row(const Energies& e, const FaceReactions& reactions,
                  const std::vector<Vec3>& prescribed, double t, Index step, double dt) {
    series.append(timeseries_row<Dim>(scene, e, reactions, prescribed, prescribed_fraction,
                                      stage_start_time + t, step, dt, stage, current_stiffness));
  }

  /// Stops the run (StateGuardError) when the guard found something; `when` says at which
  /// point of the step. A bad state is not written: the frames already on disk are the good ones.
  /// Collective in a distributed run: every rank stops with the first finding of any rank.
  void stop_if_violated(const std::optional<StateViolation>& violation,
                        const std::string& when) const {
    std::optional<std::string> found;
    if (violation)
      found = violation->describe();
    found = scene.decomposition->comm().first_message(found);
    if (found)
      throw StateGuardError(
          fmt::format("state guard: {} {}; the last good frame is frame {} (step {}, t = {:g})",
                      *found, when, writer.frames_written() - 1, last_frame_step, last_frame_time));
  }

  /// The end of the next step: the end time or the next frame time, whichever comes first.
  double target(double end_time) const {
    return frame_interval > 0 ? std::min(end_time, next_frame_time) : end_time;
  }
  void after_step(Index step, double t, double dt, const Energies& e,
                  const FaceReactions& reactions, const std::vector<Vec3>& prescribed,
                  const std::string& extra) {
    append_row(e, reactions, prescribed, t, step, dt);
    const OutputSpec& out = scene.spec.output;
    frame_at_current_step = false;
    const bool due =
        out.every_steps ? (step % *out.every_steps == 0) : (t >= next_frame_time * (1.0 - 1e-12));
    if (due) {
      write_frame(step, t);
      while (frame_interval > 0 && next_frame_time <= t * (1.0 + 1e-12))
        next_frame_time += frame_interval;
    }
    progress->update(step, t, dt, extra);
  }
  /// Makes sure the state the run ends in is a frame.
  void final_frame(Index step, double t) {
    if (!frame_at_current_step)
      write_frame(step, t);
  }
};

} // namespace talus::run_detail
