#pragma once
// Internal to run_case (src/solver/run.cpp, case_run.hpp): the stepping loops of one stage,
// explicit and implicit, and what they share: the loop's state (time, step, the checkpoint hook),
// the stage's strength factor, splitting after a step, the stop conditions.
#include "load_step_controller.hpp"
#include "newton_log.hpp"
#include "run_recorder.hpp"
#include "run_state.hpp"
#include "stage_water.hpp"
#include "talus/core/errors.hpp"
#include "talus/material/plastic_material.hpp"
#include "talus/scene/scene.hpp"
#include "talus/scene/splitting.hpp"
#include "talus/solver/explicit_solver.hpp"
#include "talus/solver/implicit_solver.hpp"
#include "talus/solver/run.hpp"
#include "talus/solver/stage_watch.hpp"
#include "talus/solver/state_guard.hpp"
#include "talus/solver/strength_reduction.hpp"

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fmt/format.h>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>

namespace talus::run_detail {

/// Set by SIGINT/SIGTERM while a run steps: the loops stop after the step in progress.
inline std::atomic<bool> g_interrupted{false};

/// Whether the run was interrupted: whether any rank was (collective), which then counts for
/// every rank, so all stop after the same step.
template <int Dim> bool interrupt_noticed(const Scene<Dim>& scene) {
  g_interrupted = scene.decomposition->comm().any(g_interrupted);
  return g_interrupted;
}

struct LoopState : LoopCounters {
  /// RunOptions::stop_after_step, and what it said when it ended the run.
  std::function<std::optional<std::string>(const StepState&)> stop_after_step{};
  std::optional<std::string> stopped{};
  bool measure_stiffness = false;               ///< RunOptions::measure_stiffness
  std::size_t measure_stiffness_from_stage = 0; ///< RunOptions::measure_stiffness_from_stage
  // --- checkpoints ---
  /// Called after each completed step and when an interrupt is noticed: writes a checkpoint
  /// when one is due (the Run decides).
  std::function<void()> checkpoint{};
  /// Adds what the stage in progress has counted but not yet put into the run's numbers.
  std::function<void(std::map<std::string, double>&)> stage_totals{};
  /// The first stage loop of a resumed run continues a stage a checkpoint interrupted.
  bool resumed_mid_stage = false;

  void checkpoint_if_due() const {
    if (checkpoint)
      checkpoint();
  }
};

/// The probes' points now and at the start, for RunOptions::stop_after_step.
template <int Dim> std::vector<ProbeState> probe_states(const Scene<Dim>& scene) {
  std::vector<ProbeState> out;
  const std::vector<ProbeReading> readings = probe_readings(scene);
  for (std::size_t k = 0; k < readings.size(); ++k)
    out.push_back({scene.probe_names[k], readings[k].x0, readings[k].x});
  return out;
}

/// Asks RunOptions::stop_after_step, if the run has one, after a completed step.
template <int Dim> void ask_stop(LoopState& s, const Scene<Dim>& scene, double time) {
  if (!s.stop_after_step)
    return;
  const std::vector<ProbeState> probes = probe_states(scene);
  s.stopped = s.stop_after_step({probes, time, s.current_stiffness});
}

/// The current stiffness after a converged quasi-static step whose compliance under its load
/// is `compliance` (NaN: not measured, the last value stands); the first one measured is the
/// reference (Bergan, Horrigmoe, Krakeland & Soreide 1978).
inline void note_compliance(LoopState& s, double compliance) {
  if (!std::isfinite(compliance) || compliance <= 0)
    return;
  if (!std::isfinite(s.reference_compliance))
    s.reference_compliance = compliance;
  s.current_stiffness = s.reference_compliance / compliance;
}

inline void check_limits(const TimeSpec& time, const LoopState& s) {
  if (s.step - s.stage_first_step >= time.max_steps)
    throw NumericalError(fmt::format("reached max_steps = {} at t = {:g} before end_time = "
                                     "{:g}; raise time.max_steps or the time step",
                                     time.max_steps, s.t, time.end_time));
}

// Time steps shorter than this fraction of the nominal step are absorbed into the previous
// one, so round-off never produces a sliver step at an output time or the end.
constexpr double kSliver = 1e-9;

/// Gives the frictional materials the strength c / F, tan(phi) / F. They keep their history;
/// only the return map changes.
template <int Dim> void set_strength(Scene<Dim>& scene, const CaseSpec& case_spec, double factor) {
  for (std::size_t m = 0; m < scene.materials.size(); ++m)
    if (auto* plastic = dynamic_cast<PlasticMaterial*>(scene.materials[m].get()))
      plastic->replace_model(make_plastic_model(
          reduce_strength(case_spec.materials[m], factor, case_spec.strength_flow_rule)));
}

/// The strength of the frictional materials during a stage: F moving from the factor the stage
/// started from to the stage's own over a quasi-static stage, or set at the start of a dynamic
/// one.
template <int Dim> class StageStrength {
public:
  /// `applied`: the factor the materials have now, kept up to date as the factor changes (the
  /// caller's record outlives a failed stage); `start`: the factor the stage started from (the
  /// previous stage's); `end`: the stage's.
  StageStrength(Scene<Dim>& scene, const CaseSpec& case_spec, double& applied, double start,
                double end)
      : scene_(scene), case_spec_(case_spec), start_(start), end_(end), applied_(applied) {}

  /// Sets the factor for a step that ends at the fraction `progress` of the stage.
  void at(double progress) {
    const double factor = scene_.spec.analysis == AnalysisType::ImplicitQuasistatic
                              ? start_ + (end_ - start_) * progress
                              : end_;
    if (factor == applied_)
      return;
    set_strength(scene_, case_spec_, factor);
    applied_ = factor;
  }
  double factor() const { return applied_; }
  double start() const { return start_; }

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
  const Index before = scene.particles.size();
  Index splits = split_material_points(scene);
  // A distributed run: every rank takes part in naming the new points, split or not.
  if (scene.distributed() && splitting_requested(scene.spec))
    splits = name_new_points(scene, before);
  if (splits == 0)
    return;
  solver.particles_changed();
  result.extra["splits"] += static_cast<double>(splits);
}

/// A distributed run partitions its cells again when the largest rank's points exceed the mean
/// by this factor. A repartition (Zoltan2 and the moves) cost 4.3 ms against a 5.1 ms step on
/// the 28k-point column collapse on two ranks, about one step; 10 % imbalance costs a tenth of
/// every step, so it pays for itself within ten steps, and the drift that follows is slow.
constexpr double kRebalanceAbove = 1.1;

/// A distributed run: the points that have left their rank's cells move to the owners'; when
/// the ranks' shares have drifted apart, the cells are partitioned again.
template <int Dim, class Solver>
void move_points_to_owners(Scene<Dim>& scene, Solver& solver, RunResult& result) {
  if (!scene.distributed())
    return;
  const Communicator& comm = scene.decomposition->comm();
  const auto moving = std::chrono::steady_clock::now();
  Index sent = migrate_points(scene).sent;
  result.extra["seconds_migration"] +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - moving).count();
  const auto start = std::chrono::steady_clock::now();
  if (const Index rebalanced = rebalance(scene, kRebalanceAbove); rebalanced >= 0) {
    sent += rebalanced;
    result.extra["repartitions"] += 1;
    result.extra["seconds_repartition"] +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  solver.particles_changed();
  result.extra["points_migrated"] += static_cast<double>(comm.sum(std::int64_t{sent}));
}

/// Writes A in Matrix Market coordinate format (both triangles, 1-based).
inline void write_matrix_market(const std::filesystem::path& file, const SparseMatrix& A) {
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
  auto solver = make_explicit_solver(scene, s.resumed_mid_stage);
  const TimeSpec& time = scene.spec.time;
  if (s.step == 0)
    rec.append_row(solver->energies(), solver->reactions(), {}, 0, 0, 0);
  // The stepping loop's own time (summary.json "seconds_stepping"): throughput figures leave
  // out building the scene and writing results.
  const auto loop_start = std::chrono::steady_clock::now();
  const double frame_seconds_before = rec.frame_seconds;
  const Index steps_before = s.step;
  const auto add_loop_time = [&](std::map<std::string, double>& x) {
    x["seconds_stepping"] +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - loop_start).count() -
        (rec.frame_seconds - frame_seconds_before);
    x["steps_stepping"] += static_cast<double>(s.step - steps_before);
  };
  const auto record_loop_time = [&] {
    add_loop_time(result.extra);
    s.stage_totals = nullptr;
  };
  s.stage_totals = add_loop_time;
  s.resumed_mid_stage = false;
  while (s.t < time.end_time * (1.0 - 1e-14)) {
    check_limits(time, s);
    if (interrupt_noticed(scene)) {
      s.checkpoint_if_due();
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
    std::optional<std::string> failure; // every rank stops together
    try {
      solver->step(dt);
    } catch (const NumericalError& e) {
      failure = e.what();
    }
    // A material that met det F <= 0 or a point that left the grid: name the point if the
    // state shows it, otherwise pass the solver's own message on.
    if (const auto first = scene.decomposition->comm().first_message(failure)) {
      guard();
      throw NumericalError(*first);
    }
    guard();
    s.t = t_end;
    ++s.step;
    const bool stage_ends = watch.ends_after_step(scene.particles, s.t, dt);
    ask_stop(s, scene, rec.stage_start_time + s.t);
    split_after_step(scene, *solver, result);
    move_points_to_owners(scene, *solver, result);
    const Energies e = solver->energies();
    if (!std::isfinite(e.kinetic) || !std::isfinite(e.strain))
      throw NumericalError("non-finite energy");
    rec.after_step(s.step, s.t, dt, e, solver->reactions(), {}, {});
    s.checkpoint_if_due();
    if (stage_ends || s.stopped)
      break;
  }
  record_loop_time();
  rec.final_frame(s.step, s.t);
  result.extra["active_nodes_last_step"] = static_cast<double>(solver->active_nodes());
}

/// Implicit analyses: load steps from the LoadStepController, each attempt's Newton residual
/// history in newton.log. A failure at the minimum step ends the run after
/// writing the last converged state as a frame. `loads_ramp`: the quasi-static loads follow
/// the stage's pseudo-time (the first stage); otherwise they act in full.
template <int Dim>
void run_implicit(Scene<Dim>& scene, Recorder<Dim>& rec, LoopState& s, RunResult& result,
                  const std::filesystem::path& out_dir, StageWatch& watch,
                  StageStrength<Dim>& strength, StageWater<Dim>& water, bool loads_ramp,
                  const std::filesystem::path& dump_tangent) {
  auto solver = make_implicit_solver(scene, loads_ramp ? 0.0 : 1.0);
  const bool measure_stiffness = s.measure_stiffness && rec.stage >= s.measure_stiffness_from_stage;
  if (measure_stiffness)
    solver->measure_load_compliance();
  result.linear_solver = solver->linear_solver();
  const TimeSpec& time = scene.spec.time;
  LoadStepController steps(time, scene.spec.solver.easy_newton_iterations, s.load_step);
  const bool resumed = s.resumed_mid_stage;
  s.resumed_mid_stage = false;
  if (resumed)
    solver->continue_from(s.continuation);
  else
    steps.start();
  NewtonLog log(out_dir, scene.decomposition->comm().root(), s.step == 0);
  if (!scene.spec.stages.empty() && !resumed)
    log.stage(rec.stage, scene.spec.stages[rec.stage].name, rec.stage_start_time);
  Index newton_iterations = 0, linear_solves = 0, linear_iterations = 0, cutbacks = 0,
        max_iterations = 0;
  rec.prescribed_fraction = solver->continuation().prescribed_fraction;
  if (s.step == 0)
    rec.append_row(solver->energies(), solver->reactions(), solver->prescribed_reactions(), 0, 0,
                   0);
  // The stage's counts into the run's numbers: at the stage's end (with its load steps), or
  // into a checkpoint's copy of them (the load steps follow from the steps then).
  // The stepping loop's own time, as the explicit loop's (summary.json "seconds_stepping").
  const auto loop_start = std::chrono::steady_clock::now();
  const double frame_seconds_before = rec.frame_seconds;
  const Index steps_before = s.step;
  auto add_totals = [&](std::map<std::string, double>& x, bool with_load_steps) {
    x["seconds_stepping"] +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - loop_start).count() -
        (rec.frame_seconds - frame_seconds_before);
    x["steps_stepping"] += static_cast<double>(s.step - steps_before);
    if (with_load_steps)
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
  };
  s.stage_totals = [&](std::map<std::string, double>& x) { add_totals(x, false); };
  auto record_totals = [&] {
    s.stage_totals = nullptr;
    add_totals(result.extra, true);
    if (!dump_tangent.empty())
      write_matrix_market(dump_tangent, solver->last_tangent());
  };
  try {
    while (s.t < time.end_time * (1.0 - 1e-14)) {
      check_limits(time, s);
      if (interrupt_noticed(scene)) {
        s.checkpoint_if_due();
        break;
      }
      const double target = rec.target(time.end_time);
      double step_dt = std::min(steps.dt(), target - s.t);
      if (s.t + step_dt * (1.0 + kSliver) >= target)
        step_dt = target - s.t;
      const double t_end = (s.t + step_dt >= target) ? target : s.t + step_dt;
      // Quasi-static loads ramp with the first stage's pseudo-time; dynamic loads act in full
      // from t = 0, and after the first stage every load does.
      const bool dynamic = scene.spec.analysis == AnalysisType::ImplicitDynamic;
      const double ramp = loads_ramp ? t_end / time.end_time : 1.0;
      strength.at(t_end / time.end_time);
      water.at(t_end / time.end_time, s.t / time.end_time);
      watch.before_step(scene.particles);
      const NewtonReport r = solver->step(dynamic ? 1.0 : ramp, ramp, step_dt);
      newton_iterations += r.iterations;
      linear_solves += r.linear_solves;
      linear_iterations += r.linear_iterations;
      log.attempt(s.step + 1, rec.stage_start_time + t_end, step_dt, r);
      if (!r.converged) {
        ++cutbacks;
        if (!steps.cut_back(step_dt))
          throw NewtonStall(fmt::format(
              "Newton did not converge at the minimum load step dt = {:g} (t = {:g} -> {:g}{}): "
              "{}",
              step_dt, s.t, t_end,
              strength.factor() != 1.0 ? fmt::format(", strength factor {:.6g}", strength.factor())
                                       : "",
              r.message));
        continue;
      }
      rec.stop_if_violated(find_particle_violation(scene.particles),
                           fmt::format("after the converged step to t = {:g}", t_end));
      max_iterations = std::max<Index>(max_iterations, r.iterations);
      s.t = t_end;
      ++s.step;
      if (measure_stiffness) // NaN in dynamics: the solver measures quasi-static steps only
        note_compliance(s, solver->load_compliance());
      const bool stage_ends = watch.ends_after_step(scene.particles, s.t, step_dt);
      ask_stop(s, scene, rec.stage_start_time + s.t);
      split_after_step(scene, *solver, result);
      move_points_to_owners(scene, *solver, result);
      steps.converged(r.iterations);
      s.continuation = solver->continuation();
      rec.prescribed_fraction = s.continuation.prescribed_fraction;
      rec.after_step(s.step, s.t, step_dt, solver->energies(), solver->reactions(),
                     solver->prescribed_reactions(),
                     fmt::format("(the step took {} Newton iterations)", r.iterations));
      s.checkpoint_if_due();
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

} // namespace talus::run_detail
