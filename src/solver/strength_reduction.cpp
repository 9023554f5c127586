#include "talus/solver/strength_reduction.hpp"

#include "talus/core/errors.hpp"
#include "talus/io/case_vocabulary.hpp"
#include "talus/io/checkpoint_file.hpp"
#include "talus/io/csv.hpp"
#include "talus/post/python_script.hpp"
#include "talus/scene/scene.hpp"
#include "talus/solver/run.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <optional>

namespace talus {

namespace fs = std::filesystem;

namespace {

constexpr double kDegree = std::numbers::pi / 180.0;

double reduced_angle(double degrees, double factor) {
  return std::atan(std::tan(degrees * kDegree) / factor) / kDegree;
}

// The files and the folder a search owns; --force replaces exactly these.
constexpr const char* kTrialsDir = "trials";
const char* const kFosEntries[] = {"fos.log",         "fos.csv",         "fos.json", "fos.png",
                                   "fos_history.csv", "fos_history.png", kTrialsDir};

// A CSV field that may hold commas or quotes.
std::string quoted(const std::string& text) {
  std::string out = "\"";
  for (const char c : text) {
    if (c == '"')
      out += '"';
    out += c;
  }
  return out + "\"";
}

/// One trial: the case with reduced strength, run quietly into `dir`; what it ended with.
StrengthTrial run_trial(const CaseSpec& spec, double factor, const fs::path& dir,
                        const FosOptions& search, bool& interrupted) {
  const StrengthReductionSpec& settings = *spec.strength_reduction;
  const auto start = std::chrono::steady_clock::now();
  RunOptions options;
  options.out_dir = dir;
  options.threads = search.threads;
  options.progress = false;
  options.measure_stiffness = true;
  const double end_time = spec.time.end_time;
  options.stop_after_step = failure_watch(
      settings, [end_time](double time) { return fmt::format("at load {:.4g}", time / end_time); });
  RunResult run;
  try {
    run = run_or_resume_trial(reduce_strength(spec, factor), options, search);
  } catch (const InputError& e) {
    // The reduced strength refused the initial stress: the slope cannot even start.
    StrengthTrial trial;
    trial.factor = factor;
    trial.failed = true;
    trial.end = TrialEnd::InitialStress;
    trial.reason = fmt::format("failed before the first step: {}", e.what());
    trial.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return trial;
  }
  if (run.status == "interrupted")
    interrupted = true;
  const CsvTable series = read_csv(dir / "timeseries.csv");
  const auto& x = series.column(settings.probe + ".x");
  const auto& y = series.column(settings.probe + ".y");
  StiffnessPath path;
  const auto& time = series.column("time");
  const auto& stiffness = series.column("current_stiffness");
  for (std::size_t r = 0; r < series.rows(); ++r)
    if (std::isfinite(stiffness[r])) {
      path.control.push_back(time[r] / end_time);
      path.stiffness.push_back(stiffness[r]);
    }
  return classify_trial(settings, factor, run, end_time, x.back() - x.front(), y.back() - y.front(),
                        path, spec.time.smallest_step() / end_time);
}

void write_fos_csv(const fs::path& file, const FactorOfSafety& fos) {
  std::ofstream out(file);
  out << "trial,factor,failed,criterion,load_reached,current_stiffness,crest_dx,crest_dy,"
         "crest_displacement,load_steps,newton_iterations,cutbacks,seconds,reason\n";
  for (std::size_t k = 0; k < fos.trials.size(); ++k) {
    const StrengthTrial& t = fos.trials[k];
    out << fmt::format(
        "{},{:.10g},{},{},{:.10g},{:.6g},{:.10g},{:.10g},{:.10g},{},{},{},{:.4g},{}\n", k + 1,
        t.factor, t.failed ? 1 : 0, to_string(t.end), t.load_reached, t.current_stiffness,
        t.crest_dx, t.crest_dy, t.crest_displacement(), t.load_steps, t.newton_iterations,
        t.cutbacks, t.seconds, quoted(t.reason));
  }
}

void write_fos_json(const fs::path& file, const CaseSpec& spec, const FosRunResult& r) {
  nlohmann::json j;
  j["case"] = spec.name;
  j["bracketed"] = r.fos.bracketed;
  j["factor_of_safety"] = r.fos.bracketed ? nlohmann::json(r.fos.value()) : nlohmann::json();
  j["bracket"] = {r.fos.lower, r.fos.upper};
  j["message"] = r.fos.message;
  j["upper_undecided"] = r.fos.upper_undecided;
  j["min_stiffness"] = spec.strength_reduction->min_stiffness;
  j["flow_rule"] = choice_word(strength_reduction_flow_choices(), spec.strength_flow_rule);
  j["trials"] = r.fos.trials.size();
  nlohmann::json ends = nlohmann::json::array();
  for (const StrengthTrial& t : r.fos.trials)
    ends.push_back({{"factor", t.factor},
                    {"failed", t.failed},
                    {"criterion", to_string(t.end)},
                    {"load_reached", t.load_reached},
                    {"current_stiffness", std::isfinite(t.current_stiffness)
                                              ? nlohmann::json(t.current_stiffness)
                                              : nlohmann::json()},
                    {"crest_displacement", t.crest_displacement()}});
  j["trial_ends"] = ends;
  if (!r.history.empty()) {
    nlohmann::json history = nlohmann::json::array();
    for (const StageFactorOfSafety& h : r.history)
      history.push_back(
          {{"stage", h.stage},
           {"time", h.time},
           {"bracketed", h.fos.bracketed},
           {"factor_of_safety", h.fos.bracketed ? nlohmann::json(h.fos.value()) : nlohmann::json()},
           {"bracket", {h.fos.lower, h.fos.upper}},
           {"message", h.fos.message}});
    j["history"] = history;
  }
  j["newton_iterations"] = r.newton_iterations;
  j["wall_seconds"] = r.wall_seconds;
  j["cpu_seconds"] = r.cpu_seconds;
  std::ofstream(file) << j.dump(2) << "\n";
}

void write_fos_history_csv(const fs::path& file, const std::vector<StageFactorOfSafety>& history) {
  std::ofstream out(file);
  out << "stage,time,lower,upper,factor_of_safety,bracketed,steps,seconds,message\n";
  for (const StageFactorOfSafety& h : history) {
    double seconds = 0;
    for (const StrengthTrial& t : h.fos.trials)
      seconds += t.seconds;
    out << fmt::format("{},{:.10g},{:.10g},{:.10g},{:.10g},{},{},{:.4g},{}\n", h.stage, h.time,
                       h.fos.lower, h.fos.upper, h.fos.value(), h.fos.bracketed ? 1 : 0,
                       h.fos.trials.size(), seconds, quoted(h.fos.message));
  }
}

/// Halves [fos.lower, fos.upper] (a standing and a failing factor) until it is within the
/// tolerance or the trials run out.
template <class Run, class OutOfTrials>
FactorOfSafety& bisect(const StrengthReductionSpec& settings, FactorOfSafety& fos, Run& run,
                       OutOfTrials& out_of_trials) {
  while (fos.upper - fos.lower > settings.tolerance) {
    if (out_of_trials()) {
      fos.message = fmt::format("max_trials = {} reached with the bracket [{:g}, {:g}] wider "
                                "than the tolerance {:g}",
                                settings.max_trials, fos.lower, fos.upper, settings.tolerance);
      return fos;
    }
    const double middle = 0.5 * (fos.lower + fos.upper);
    (run(middle) ? fos.lower : fos.upper) = middle;
  }
  fos.bracketed = true;
  fos.message = fmt::format("bracket [{:.4g}, {:.4g}] within the tolerance {:g} after {} trials",
                            fos.lower, fos.upper, settings.tolerance, fos.trials.size());
  return fos;
}

/// Davis's associated equivalent of (c, phi) with dilation psi (degrees), in place.
void davis_strength(double& cohesion, double& friction_angle, double dilation_angle) {
  const double to_rad = std::numbers::pi / 180.0;
  const double phi = friction_angle * to_rad, psi = dilation_angle * to_rad;
  const double beta = std::cos(psi) * std::cos(phi) / (1.0 - std::sin(psi) * std::sin(phi));
  cohesion *= beta;
  friction_angle = std::atan(beta * std::tan(phi)) / to_rad;
}

} // namespace

MaterialSpec reduce_strength(const MaterialSpec& material, double factor,
                             StrengthReductionFlow flow) {
  MaterialSpec m = material;
  if (m.model != MaterialModel::Tresca && m.model != MaterialModel::MohrCoulomb &&
      m.model != MaterialModel::DruckerPrager)
    return m;
  m.cohesion /= factor;
  m.friction_angle = reduced_angle(m.friction_angle, factor);
  if (m.residual) {
    m.residual->cohesion /= factor;
    m.residual->friction_angle = reduced_angle(m.residual->friction_angle, factor);
  }
  // psi may not exceed phi at any point of the softening either.
  m.dilation_angle = std::min(
      {m.dilation_angle, m.friction_angle, m.residual ? m.residual->friction_angle : 90.0});
  if (flow == StrengthReductionFlow::Davis && m.model != MaterialModel::Tresca) {
    const double psi = m.dilation_angle;
    davis_strength(m.cohesion, m.friction_angle, psi);
    m.dilation_angle = m.friction_angle;
    if (m.residual) {
      davis_strength(m.residual->cohesion, m.residual->friction_angle, psi);
      m.dilation_angle = std::min(m.dilation_angle, m.residual->friction_angle);
    }
  }
  return m;
}

CaseSpec reduce_strength(const CaseSpec& spec, double factor) {
  CaseSpec reduced = spec;
  for (MaterialSpec& m : reduced.materials)
    m = reduce_strength(m, factor, spec.strength_flow_rule);
  return reduced;
}

FactorOfSafety search_factor_of_safety(const StrengthReductionSpec& settings,
                                       const std::function<StrengthTrial(double)>& trial,
                                       const std::function<void(const StrengthTrial&)>& on_trial,
                                       double floor) {
  FactorOfSafety fos;
  auto run = [&](double factor) {
    fos.trials.push_back(trial(factor));
    if (on_trial)
      on_trial(fos.trials.back());
    return !fos.trials.back().failed;
  };
  auto out_of_trials = [&] { return static_cast<int>(fos.trials.size()) >= settings.max_trials; };
  // Below `lower` down to `floor`, in steps that double, until a factor stands.
  double lower = settings.lower;
  double step = settings.upper - settings.lower;
  while (!run(lower)) {
    fos.upper = lower;
    if (lower <= floor || out_of_trials()) {
      fos.message = fmt::format("the lowest factor F = {:g} already fails: the factor of safety "
                                "is below the search range; lower strength_reduction.lower",
                                lower);
      return fos;
    }
    lower = std::max(floor, lower - step);
    step *= 2;
  }
  if (lower < settings.lower) { // a standing factor below the range: bisect [lower, upper]
    fos.lower = lower;
    return bisect(settings, fos, run, out_of_trials);
  }
  fos.lower = settings.lower;
  double upper = settings.upper;
  while (true) {
    if (out_of_trials()) {
      fos.message = fmt::format("no failing factor found within max_trials = {}: the factor of "
                                "safety is above {:g}; raise strength_reduction.upper",
                                settings.max_trials, fos.lower);
      return fos;
    }
    if (!run(upper))
      break;
    fos.lower = upper;
    upper *= 1.5;
  }
  fos.upper = upper;
  return bisect(settings, fos, run, out_of_trials);
}

namespace {

/// Marks a search whose smallest failed factor Newton could not decide, and says so.
void note_undecided_upper(FactorOfSafety& fos) {
  const auto upper = std::find_if(fos.trials.begin(), fos.trials.end(),
                                  [&](const auto& t) { return t.failed && t.factor == fos.upper; });
  fos.upper_undecided = upper != fos.trials.end() && upper->end == TrialEnd::NewtonBudget;
  if (fos.upper_undecided)
    fos.message += fmt::format("; but the trial F = {:g} that bounds it above was undecided "
                               "(Newton's budget, not a mechanism): the factor of safety may be "
                               "higher",
                               fos.upper);
}

/// A finished run's result as its summary.json tells it; nothing if it did not finish.
std::optional<RunResult> finished_run(const fs::path& dir) {
  std::ifstream in(dir / "summary.json");
  if (!in)
    return std::nullopt;
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  if (j.is_discarded() || j.value("status", "") == "interrupted")
    return std::nullopt;
  RunResult r;
  r.out_dir = dir;
  r.status = j.value("status", "");
  r.message = j.value("message", "");
  r.steps = j.value("steps", Index{0});
  r.final_time = j.value("final_time", 0.0);
  r.frames = j.value("frames", Index{0});
  r.particles = j.value("particles", Index{0});
  r.wall_seconds = j.value("wall_seconds", 0.0);
  r.linear_solver = j.value("linear_solver", "");
  r.exit_code = r.status == "completed"           ? kExitOk
                : r.status == "numerical_failure" ? kExitNumerical
                                                  : kExitOther;
  for (const auto& [key, value] : j.items())
    if (value.is_number() && !value.is_number_integer())
      r.extra[key] = value.get<double>();
  return r;
}

} // namespace

std::optional<std::string> undrained_dilatancy_warning(const CaseSpec& spec) {
  if (!spec.consolidates() || !spec.strength_reduction ||
      spec.strength_reduction->mode != StrengthReductionMode::Incremental)
    return std::nullopt;
  std::vector<std::string> dilatant;
  for (const MaterialSpec& m : spec.materials) // as the search weakens it (Davis: associated)
    if (const double psi = reduce_strength(m, 1.0, spec.strength_flow_rule).dilation_angle; psi > 0)
      dilatant.push_back(fmt::format("'{}' (dilation angle {:g} deg)", m.name, psi));
  if (dilatant.empty())
    return std::nullopt;
  return fmt::format("the strength is lowered undrained, and {} dilate{} as {} shear{}: the "
                     "suction adds strength, and the factor may be well above that of a failure "
                     "with drainage (docs/case-format.md, A staged case); give dilation_angle: 0 "
                     "where undrained failure matters",
                     fmt::join(dilatant, ", "), dilatant.size() == 1 ? "s" : "",
                     dilatant.size() == 1 ? "it" : "they", dilatant.size() == 1 ? "s" : "");
}

RunResult run_or_resume_trial(const CaseSpec& spec, RunOptions options, const FosOptions& search) {
  if (search.resume && fs::exists(options.out_dir)) {
    if (auto finished = finished_run(options.out_dir))
      return *finished;
    options.resume = !list_checkpoints(options.out_dir / "checkpoints").empty();
    options.accept_changes = search.accept_changes;
    options.force = !options.resume;
  }
  return run_case(spec, options);
}

FosRunResult run_factor_of_safety(const CaseSpec& spec, const FosOptions& options) {
  if (!spec.strength_reduction)
    throw InputError({spec.source_file, 0, 0, "strength_reduction"},
                     "talus fos needs a 'strength_reduction' section in the case (at least its "
                     "crest 'probe'); see docs/case-format.md");
  const auto wall_start = std::chrono::steady_clock::now();
  const std::clock_t cpu_start = std::clock();
  // Under mpirun every rank runs each trial's run; rank 0 alone writes the search's files.
  const Communicator& ranks = Communicator::world();
  FosRunResult result;
  result.out_dir =
      options.out_dir.empty() ? fs::path("results") / (spec.name + "-fos") : options.out_dir;
  if (options.resume) {
    if (!fs::is_directory(result.out_dir / kTrialsDir))
      throw InputError({"--resume", 0, 0, ""},
                       fmt::format("'{}' holds no search to resume (no '{}' folder)",
                                   result.out_dir.string(), kTrialsDir));
  }
  on_root(ranks, [&] {
    if (!options.resume)
      claim_output_directory(result.out_dir, options.force, kFosEntries);
    fs::create_directories(result.out_dir / kTrialsDir);
  });
  std::ofstream log; // closed on the other ranks: their writes go nowhere
  if (ranks.root())
    log.open(result.out_dir / "fos.log");
  log << fmt::format("# talus fos {}: strength reduction c / F, tan(phi) / F; a trial fails when "
                     "the slope's current stiffness under its weight falls below {:g} of its "
                     "first load step's (a mechanism){}; checked after every converged load "
                     "step, where the trial stops\n",
                     spec.name, spec.strength_reduction->min_stiffness,
                     spec.strength_reduction->displacement_limit
                         ? fmt::format(" or the crest moves more than {:g} m",
                                       *spec.strength_reduction->displacement_limit)
                         : std::string());
  if (const auto warning = undrained_dilatancy_warning(spec)) {
    log << "# warning: " << *warning << "\n";
    if (ranks.root())
      fmt::print(stderr, "talus: warning: {}\n", *warning);
  }
  bool interrupted = false;
  auto trial = [&](double factor) {
    if (interrupted) { // stop at once, the user asked to
      StrengthTrial t;
      t.factor = factor;
      t.failed = true;
      t.end = TrialEnd::Interrupted;
      t.reason = "interrupted";
      return t;
    }
    const fs::path dir = result.out_dir / kTrialsDir / fmt::format("F{:.6f}", factor);
    return run_trial(spec, factor, dir, options, interrupted);
  };
  auto on_trial = [&](const StrengthTrial& t) {
    const std::string line =
        fmt::format("trial F = {:.6f}: {} ({:.2f} s)", t.factor, t.reason, t.seconds);
    log << line << "\n" << std::flush;
    if (ranks.root()) {
      fmt::print("{}\n", line);
      std::fflush(stdout);
    }
  };
  // Loaded at a lower factor again (a fresh run) while the loading fails above `floor`.
  auto incremental = [&](CaseSpec attempt, const fs::path& dir) {
    StrengthReductionSpec& settings = *attempt.strength_reduction;
    double step = settings.upper - settings.lower;
    while (true) {
      FactorOfSafety fos = incremental_factor_of_safety(attempt, dir, options, interrupted);
      for (const StrengthTrial& t : fos.trials)
        log << fmt::format("step F = {:.6f}: {}\n", t.factor, t.reason);
      const bool below = !fos.trials.empty() && fos.trials.front().failed;
      if (!below || interrupted || settings.lower <= options.floor)
        return fos;
      settings.lower = std::max(options.floor, settings.lower - step);
      step *= 2;
      fs::remove_all(dir);
    }
  };
  if (!spec.stages.empty()) { // the history to each stage searched after, then its search
    for (const std::size_t k : spec.strength_reduction->after_stages) {
      CaseSpec history = spec;
      history.stages.resize(k + 1);
      StageFactorOfSafety h;
      h.stage = spec.stages[k].name;
      for (const StageSpec& stage : history.stages)
        h.time += stage.time.end_time;
      log << fmt::format("# after stage '{}' (t = {:g} s)\n", h.stage, h.time);
      h.fos = incremental(history, result.out_dir / kTrialsDir / ("after_" + h.stage));
      log << fmt::format("# after stage '{}': {}\n", h.stage, h.fos.message);
      if (ranks.root())
        fmt::print("after stage '{}' (t = {:g} s): {}\n", h.stage, h.time, h.fos.message);
      result.history.push_back(std::move(h));
      if (interrupted)
        break;
    }
    result.fos = result.history.back().fos;
    for (const StageFactorOfSafety& h : result.history)
      result.fos.bracketed = result.fos.bracketed && h.fos.bracketed;
  } else if (spec.strength_reduction->mode == StrengthReductionMode::Incremental) {
    result.fos = incremental(spec, result.out_dir / kTrialsDir / "incremental");
  } else {
    result.fos = search_factor_of_safety(*spec.strength_reduction, trial, on_trial, options.floor);
  }
  note_undecided_upper(result.fos);
  if (interrupted) {
    result.fos.bracketed = false;
    result.fos.message = "interrupted";
  }
  for (const StrengthTrial& t : result.fos.trials)
    result.newton_iterations += t.newton_iterations;
  for (std::size_t k = 0; k + 1 < result.history.size(); ++k)
    for (const StrengthTrial& t : result.history[k].fos.trials)
      result.newton_iterations += t.newton_iterations;
  result.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  result.cpu_seconds = static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC;
  result.exit_code = interrupted ? kExitOther : result.fos.bracketed ? kExitOk : kExitNumerical;
  log << fmt::format("# {}; {} Newton iterations, {:.2f} s ({:.2f} s of CPU)\n", result.fos.message,
                     result.newton_iterations, result.wall_seconds, result.cpu_seconds);
  on_root(ranks, [&] {
    write_fos_csv(result.out_dir / "fos.csv", result.fos);
    write_fos_json(result.out_dir / "fos.json", spec, result);
    run_python_script(
        "plot_fos.py",
        {(result.out_dir / "fos.csv").string(), (result.out_dir / "fos.png").string(), spec.name,
         fmt::format("{:.17g}", result.fos.lower), fmt::format("{:.17g}", result.fos.upper),
         result.fos.bracketed ? "1" : "0",
         fmt::format("{:g}", spec.strength_reduction->min_stiffness),
         choice_word(strength_reduction_mode_choices(), spec.strength_reduction->mode)});
    if (!result.history.empty()) {
      write_fos_history_csv(result.out_dir / "fos_history.csv", result.history);
      run_python_script("plot_fos_history.py",
                        {(result.out_dir / "fos_history.csv").string(),
                         (result.out_dir / "fos_history.png").string(), spec.name});
    }
  });
  return result;
}

} // namespace talus
