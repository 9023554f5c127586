// `talus bench --case newton_cost`: what an implicit Newton iteration costs against a bare
// factorisation + solve of its own tangent by the same backend (include/talus/verify/bench.hpp).
//
// Measurement choices:
//  * The beams are `cases/cantilever_large.yaml` (1600 points), the same beam 4x finer (cell
//    size halved: 6400 points) and a 3D Hencky cantilever (verification/cantilever_3d.yaml, 4
//    cells through the depth, 4 load steps). Each run is a child process.
//  * One extra run writes the last tangent (`--dump-tangent`); Google Benchmark (talus_bench,
//    BM_DumpedTangent) then times its analysis and its factorisation + solve, medians of the
//    repeats. A Newton iteration's time is the run's wall time (summary.json, without process
//    start-up) over its Newton iterations; the phases are the run's own summary.json split.
//  * `--vs OLD_TALUS` runs an older binary on the same case alternately with this one, repeat
//    by repeat, and reports the median ratio of whole-process wall times (start-up included, the
//    only time an older binary reports the same way).
//  * Memory per point: the peak resident set less the binary's own (`talus info`), over points.
#include "talus/verify/bench.hpp"

#include "child_process.hpp"

#include "talus/core/errors.hpp"
#include "talus/verify/verification.hpp"

#include <cmath>
#include <cstdlib>
#include <fmt/format.h>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

namespace talus {

namespace fs = std::filesystem;
using namespace bench_detail;

namespace {

/// summary.json's phases (seconds_<phase>), in the order they add up to wall_seconds.
const std::vector<std::string> kPhases = {"step_setup",
                                          "material",
                                          "residual_assembly",
                                          "tangent_assembly",
                                          "analysis",
                                          "factorization",
                                          "solve",
                                          "commit",
                                          "output",
                                          "other"};

/// The phases repeated every Newton iteration (the rest is paid once per load step or run).
const std::vector<std::string> kIterationPhases = {"material", "residual_assembly",
                                                   "tangent_assembly", "factorization", "solve"};

struct NewtonCostConfig {
  std::string label;
  fs::path case_file;
  std::vector<std::string> overrides;
};

struct NewtonCostRow {
  NewtonCostConfig config;
  double particles = NAN;
  double unknowns = NAN;
  double newton_iterations = NAN;
  double load_steps = NAN;
  double wall_seconds = NAN;                   ///< median run_case wall time
  std::map<std::string, double> phase_seconds; ///< medians
  double bare_factor_solve_ms = NAN;
  double bare_analysis_ms = NAN;
  double peak_rss_mb = NAN;
  double bytes_per_point = NAN;
  double process_seconds = NAN;          ///< median whole-process wall time of this binary
  double baseline_process_seconds = NAN; ///< the same of --vs
  double ratio_to_baseline = NAN;        ///< median of the pairs' this / baseline
  std::string linear_solver;
  std::string status = "ok";
  std::string message;

  double ms_per_iteration() const { return 1e3 * wall_seconds / newton_iterations; }
  double iteration_work_ms() const {
    double s = 0;
    for (const auto& p : kIterationPhases)
      s += phase_seconds.at(p);
    return 1e3 * s / newton_iterations;
  }
};

std::vector<NewtonCostConfig> newton_cost_sweep() {
  const fs::path cases = verification_dir().parent_path() / "cases";
  return {{"cantilever_large", cases / "cantilever_large.yaml", {}},
          {"cantilever_large_4x", cases / "cantilever_large.yaml", {"grid.cell_size=0.05"}},
          {"cantilever_3d_hencky",
           verification_dir() / "cantilever_3d.yaml",
           {"grid.cell_size=0.25", "materials[0].model=hencky", "time.dt=0.25"}}};
}

std::vector<std::string> run_arguments(const NewtonCostConfig& c, const fs::path& dir,
                                       int threads) {
  std::vector<std::string> args = {
      "run",       c.case_file.string(),   "--out", dir.string(), "--force",
      "--threads", std::to_string(threads)};
  for (const auto& o : c.overrides) {
    args.push_back("--set");
    args.push_back(o);
  }
  return args;
}

/// talus_bench beside this binary (build/bench/talus_bench), or empty when it was not built.
fs::path kernel_bench_binary() {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  const fs::path bench = self.parent_path() / "bench" / "talus_bench";
  return !ec && fs::exists(bench) ? bench : fs::path();
}

/// Times the dumped tangent with Google Benchmark: {factor + solve, analysis} medians in ms.
std::pair<double, double> time_dumped_tangent(const fs::path& tangent, const std::string& solver,
                                              int repeats, const fs::path& dir) {
  const fs::path bench = kernel_bench_binary();
  if (bench.empty())
    throw std::runtime_error("talus_bench was not built (configure with TALUS_BUILD_BENCH=ON)");
  const fs::path out = dir / "dumped_tangent.json";
  // The child inherits the environment: the file and the backend of the run.
  setenv("TALUS_TANGENT", tangent.c_str(), 1);
  setenv("TALUS_TANGENT_SOLVER", solver.c_str(), 1);
  const ChildResult r = spawn_and_wait(
      bench,
      {"--benchmark_filter=DumpedTangent", fmt::format("--benchmark_repetitions={}", repeats),
       "--benchmark_report_aggregates_only=true", "--benchmark_out_format=json",
       "--benchmark_out=" + out.string()},
      dir / "talus_bench.log");
  unsetenv("TALUS_TANGENT");
  unsetenv("TALUS_TANGENT_SOLVER");
  if (r.exit_code != 0)
    throw std::runtime_error(failure_message(dir / "talus_bench.log", r.exit_code));
  double factor_solve = NAN, analysis = NAN;
  const auto report = nlohmann::json::parse(read_text(out));
  for (const auto& b : report.at("benchmarks")) {
    if (b.value("aggregate_name", "") != "median")
      continue;
    const std::string name =
        b.value("run_name", ""); // e.g. BM_DumpedTangent/cholmod/analyze/real_time
    const double ms = b.at("real_time").get<double>(); // registered with kMillisecond
    if (name.find("/factor_solve") != std::string::npos)
      factor_solve = ms;
    else if (name.find("/analyze") != std::string::npos)
      analysis = ms;
  }
  if (!std::isfinite(factor_solve) || !std::isfinite(analysis))
    throw std::runtime_error("no medians of BM_DumpedTangent in " + out.string());
  return {factor_solve, analysis};
}

NewtonCostRow run_newton_cost(const NewtonCostConfig& c, const BenchOptions& options,
                              double baseline_mb, const fs::path& exe, const fs::path& runs_dir) {
  NewtonCostRow row;
  row.config = c;
  const fs::path dir = runs_dir / c.label;
  const fs::path old_dir = dir / "baseline";
  fs::create_directories(old_dir);
  const fs::path log = dir / "talus.log";
  const auto args = run_arguments(c, dir, options.threads);
  std::vector<double> wall, process, baseline, ratio;
  std::map<std::string, std::vector<double>> phases;
  double peak = 0;
  try {
    // The tangent for the kernel benchmark, from a run of its own (writing it is not timed).
    auto dump_args = args;
    dump_args.insert(dump_args.end(), {"--dump-tangent", (dir / "tangent.mtx").string()});
    ChildResult r = spawn_and_wait(exe, dump_args, log);
    if (r.exit_code != 0)
      throw std::runtime_error(failure_message(log, r.exit_code));
    for (int k = 0; k < options.repeats; ++k) {
      if (!options.baseline.empty()) {
        const ChildResult old = spawn_and_wait(
            options.baseline, run_arguments(c, old_dir, options.threads), old_dir / "talus.log");
        if (old.exit_code != 0)
          throw std::runtime_error("--vs binary: " +
                                   failure_message(old_dir / "talus.log", old.exit_code));
        baseline.push_back(old.wall_seconds);
      }
      fs::remove(dir / "summary.json");
      r = spawn_and_wait(exe, args, log);
      if (r.exit_code != 0)
        throw std::runtime_error(failure_message(log, r.exit_code));
      peak = std::max(peak, r.max_rss_mb);
      process.push_back(r.wall_seconds);
      if (!baseline.empty())
        ratio.push_back(r.wall_seconds / baseline.back());
      const auto summary = nlohmann::json::parse(read_text(dir / "summary.json"));
      wall.push_back(json_number(summary, "wall_seconds"));
      for (const auto& p : kPhases)
        phases[p].push_back(json_number(summary, "seconds_" + p));
      row.particles = json_number(summary, "particles");
      row.unknowns = json_number(summary, "unknowns_last_step");
      row.newton_iterations = json_number(summary, "newton_iterations");
      row.load_steps = json_number(summary, "load_steps");
      row.linear_solver = summary.value("linear_solver", "");
    }
    std::tie(row.bare_factor_solve_ms, row.bare_analysis_ms) =
        time_dumped_tangent(dir / "tangent.mtx", row.linear_solver, options.repeats, dir);
  } catch (const std::exception& e) {
    row.status = "failed";
    row.message = e.what();
  }
  if (!wall.empty()) {
    row.wall_seconds = median(wall);
    row.process_seconds = median(process);
    for (const auto& p : kPhases)
      row.phase_seconds[p] = median(phases[p]);
  }
  if (!baseline.empty()) {
    row.baseline_process_seconds = median(baseline);
    row.ratio_to_baseline = median(ratio);
  }
  if (peak > 0) {
    row.peak_rss_mb = peak;
    row.bytes_per_point = (peak - baseline_mb) * 1024.0 * 1024.0 / row.particles;
  }
  return row;
}

void write_newton_cost_csv(const fs::path& file, const std::vector<NewtonCostRow>& rows) {
  std::ofstream out(file);
  if (!out)
    throw std::runtime_error("cannot create " + file.string());
  out << "case,linear_solver,particles,unknowns,load_steps,newton_iterations,wall_seconds,";
  for (const auto& p : kPhases)
    out << "seconds_" << p << ",";
  out << "ms_per_iteration,iteration_work_ms,bare_factor_solve_ms,bare_analysis_ms,"
         "ratio_iteration_to_bare,process_seconds,baseline_process_seconds,ratio_to_baseline,"
         "peak_rss_mb,bytes_per_point,status,message\n";
  for (const auto& r : rows) {
    const bool ok = r.status == "ok";
    out << fmt::format("{},{},{},{},{},{},{},", r.config.label, r.linear_solver,
                       csv_number(r.particles), csv_number(r.unknowns), csv_number(r.load_steps),
                       csv_number(r.newton_iterations), csv_number(r.wall_seconds));
    for (const auto& p : kPhases)
      out << csv_number(ok ? r.phase_seconds.at(p) : NAN) << ",";
    out << fmt::format("{},{},{},{},{},{},{},{},{},{},{},\"{}\"\n",
                       csv_number(ok ? r.ms_per_iteration() : NAN),
                       csv_number(ok ? r.iteration_work_ms() : NAN),
                       csv_number(r.bare_factor_solve_ms), csv_number(r.bare_analysis_ms),
                       csv_number(ok ? r.ms_per_iteration() / r.bare_factor_solve_ms : NAN),
                       csv_number(r.process_seconds), csv_number(r.baseline_process_seconds),
                       csv_number(r.ratio_to_baseline), csv_number(r.peak_rss_mb),
                       csv_number(r.bytes_per_point), r.status, r.message);
  }
}

void print_newton_cost_table(const std::vector<NewtonCostRow>& rows, const BenchOptions& options,
                             double baseline_mb) {
  fmt::print("Newton iteration cost ({} repeats, {} thread(s); an iteration is run wall / Newton "
             "iterations, 'work' its material + assembly + factorisation + solve; 'bare' is "
             "talus_bench's factor + solve of the run's last tangent; memory: peak RSS less the "
             "binary's {:.0f} MB)\n",
             options.repeats, options.threads, baseline_mb);
  fmt::print("{:<22} {:>6} {:>8} {:>6} {:>9} {:>9} {:>9} {:>9} {:>7} {:>8} {:>8}  {}\n", "case",
             "points", "unknowns", "newton", "iter ms", "work ms", "bare ms", "analys ms", "ratio",
             "B/point", "vs old", "status");
  fmt::print("{}\n", std::string(120, '-'));
  for (const auto& r : rows) {
    const bool ok = r.status == "ok";
    fmt::print("{:<22} {:>6} {:>8} {:>6} {:>9} {:>9} {:>9} {:>9} {:>7} {:>8} {:>8}  {}{}\n",
               r.config.label, cell(r.particles, "{:.0f}"), cell(r.unknowns, "{:.0f}"),
               cell(r.newton_iterations, "{:.0f}"), cell(ok ? r.ms_per_iteration() : NAN, "{:.2f}"),
               cell(ok ? r.iteration_work_ms() : NAN, "{:.2f}"),
               cell(r.bare_factor_solve_ms, "{:.2f}"), cell(r.bare_analysis_ms, "{:.2f}"),
               cell(ok ? r.ms_per_iteration() / r.bare_factor_solve_ms : NAN, "{:.2f}"),
               cell(r.bytes_per_point, "{:.0f}"), cell(r.ratio_to_baseline, "{:.3f}"), r.status,
               r.message.empty() ? "" : " (" + r.message + ")");
  }
}

} // namespace

int run_newton_cost_bench(const BenchOptions& options) {
  const fs::path plot_script = verification_dir().parent_path() / "scripts" / "plot_newton_cost.py";
  if (!fs::exists(plot_script))
    throw std::runtime_error("plot script not found: " + plot_script.string());
  const fs::path exe = "/proc/self/exe";
  const fs::path out =
      options.out_dir.empty() ? fs::path("results") / "bench" / "newton_cost" : options.out_dir;
  const fs::path runs = out / "runs";
  fs::create_directories(runs);
  const double baseline_mb = spawn_and_wait(exe, {"info"}, runs / "baseline.log").max_rss_mb;

  const auto configs = newton_cost_sweep();
  std::vector<NewtonCostRow> rows;
  for (std::size_t i = 0; i < configs.size(); ++i) {
    fmt::print(stderr, "bench [{}/{}] {} ... ", i + 1, configs.size(), configs[i].label);
    std::fflush(stderr);
    rows.push_back(run_newton_cost(configs[i], options, baseline_mb, exe, runs));
    const NewtonCostRow& r = rows.back();
    if (r.status == "ok")
      fmt::print(stderr, "{:.2f} ms per Newton iteration, bare factor + solve {:.2f} ms\n",
                 r.ms_per_iteration(), r.bare_factor_solve_ms);
    else
      fmt::print(stderr, "FAILED: {}\n", r.message);
  }
  const fs::path csv = out / "newton_cost.csv";
  write_newton_cost_csv(csv, rows);
  print_newton_cost_table(rows, options, baseline_mb);

  plot_table(plot_script, csv, out / "newton_cost.png");
  return kExitOk;
}

} // namespace talus
