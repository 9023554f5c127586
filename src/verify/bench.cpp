// `talus bench`: work-precision sweeps over verification cases (see
// include/talus/verify/bench.hpp).
//
// Measurement choices:
//  * Each run is a child process, `talus run verification/<case>.yaml --out <dir> --force
//    --set ...` (the binary re-executes its own image through /proc/self/exe). The parent waits
//    with wait4 and takes ru_maxrss, the child's own peak resident set, so the memory column is per
//    run and not the parent's monotone high-water mark. It includes the binary's fixed
//    footprint (shared libraries: Trilinos, MPI, HDF5, ...), which the table header reports as
//    the baseline measured on `talus info`.
//  * The time of a run is the child's run_case wall time (summary.json "wall_seconds": scene
//    build, solve and result writing), not process start-up. Median and minimum over repeats.
//  * The error is computed from the last repeat's results with the same formulas as the
//    verification cases (the runs are deterministic for a fixed thread count).
//  * Errors come from src/verify/references.hpp, shared with the verification cases.
#include "talus/verify/bench.hpp"

#include "child_process.hpp"
#include "references.hpp"

#include "talus/core/errors.hpp"
#include "talus/io/csv.hpp"
#include "talus/io/results.hpp"
#include "talus/linalg/linear_solver.hpp"
#include "talus/verify/verification.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

namespace talus {

namespace fs = std::filesystem;

using namespace bench_detail;

namespace {

// --- errors, from the shared references (the same formulas as the verification cases) ---

double cantilever_error(const fs::path& run_dir) {
  double x = 0;
  const Vec3 u = references::tip_column_displacement(ResultsReader(run_dir / "run.h5"), &x);
  return std::abs(u.y() / references::cantilever_deflection(x, 1.0) - 1.0);
}

// The compressed column of the sweep (column_large_compression): rho g H / E = 4.
constexpr double kColumnRatio = 4.0;

// The large-deflection beam of the sweep: the 50 load steps to alpha = 2.
constexpr double kLargeDeflectionAlpha = 2.0;
constexpr int kLargeDeflectionSteps = 50;

double vibrating_bar_error(const fs::path& run_dir, int n) {
  const double h = references::kBarLength / n;
  return references::vibrating_bar_rms_error(read_csv(run_dir / "timeseries.csv"),
                                             references::kBarDensity * references::kBarLength * h);
}

// --- the sweep --------------------------------------------------------------------------------

struct Config {
  std::string shape;
  std::string backend; ///< linear solver, or "explicit"
  int cells = 0;       ///< through the depth (cantilever) or along the bar (vibrating_bar)
  std::vector<std::string> overrides;
};

struct Row {
  Config config;
  double particles = NAN;
  double unknowns = NAN;
  double error = NAN;
  double median_seconds = NAN;
  double min_seconds = NAN;
  int repeats = 0; ///< completed repeats
  double newton_iterations = NAN;
  double peak_rss_mb = NAN;
  std::string status;
  std::string message;
};

/// The shapes beside linear hats and uGIMP: swept with the default backend only (the backends
/// are compared on the two older shapes).
const std::vector<std::string> kNewShapes = {"cpgimp", "cpdi", "bspline2", "bspline3"};

std::vector<Config> sweep(const std::string& name, bool quick) {
  std::vector<Config> configs;
  const std::vector<std::string> shapes = {"linear", "gimp"};
  if (name == "cantilever") {
    std::vector<int> cells = {2, 4, 8, 16};
    if (quick)
      cells.pop_back();
    const auto add = [&](const std::string& shape, const std::string& backend, int n) {
      configs.push_back({shape,
                         backend,
                         n,
                         {fmt::format("grid.cell_size={:.17g}", references::kBeamDepth / n),
                          "solver.shape=" + shape, "solver.linear_solver=" + backend}});
    };
    for (const auto& shape : shapes)
      for (const auto& backend : available_linear_solvers())
        for (const int n : cells)
          add(shape, backend, n);
    for (const auto& shape : kNewShapes)
      for (const int n : cells)
        add(shape, "cholmod", n);
  } else if (name == "column_large_compression") {
    // rho g H / E = 4: the base squeezed to 35 % of its height.
    std::vector<int> cells = {8, 16, 32, 64};
    if (quick)
      cells.pop_back();
    for (const auto& shape : {"gimp", "cpgimp", "cpdi", "bspline2", "bspline3"})
      for (const int n : cells) {
        auto overrides = references::compressed_column_overrides(n, kColumnRatio);
        overrides.push_back(std::string("solver.shape=") + shape);
        configs.push_back({shape, "cholmod", n, overrides});
      }
  } else if (name == "cantilever_large") {
    std::vector<int> cells = {4, 5, 6, 8, 16};
    if (quick)
      cells.pop_back();
    for (const auto& backend : {"cholmod", "umfpack", "klu"})
      for (const int n : cells) {
        auto overrides =
            references::large_deflection_overrides(kLargeDeflectionAlpha, kLargeDeflectionSteps, n);
        overrides.push_back(std::string("solver.linear_solver=") + backend);
        configs.push_back({"gimp", backend, n, overrides});
      }
  } else {
    std::vector<int> cells = {16, 32, 64, 128};
    if (quick)
      cells.pop_back();
    for (const auto& shape : shapes)
      for (const int n : cells) {
        auto overrides = references::vibrating_bar_overrides(n);
        overrides.push_back("solver.shape=" + shape);
        configs.push_back({shape, "explicit", n, overrides});
      }
    // Three cells high: the cubic splines need three cells on every axis.
    for (const auto& shape : kNewShapes)
      for (const int n : cells) {
        auto overrides = references::vibrating_bar_overrides(n, 2, 3);
        overrides.push_back("solver.shape=" + shape);
        configs.push_back({shape, "explicit", n, overrides});
      }
  }
  return configs;
}

std::string csv_text(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos)
    return s;
  std::string q = "\"";
  for (char c : s)
    q += (c == '"') ? std::string("\"\"") : std::string(1, c == '\n' ? ' ' : c);
  return q + "\"";
}

Row run_configuration(const std::string& case_name, const Config& c, const BenchOptions& options,
                      const fs::path& exe, const fs::path& case_file, const fs::path& runs_dir) {
  Row row;
  row.config = c;
  const fs::path dir = runs_dir / fmt::format("{}_{}_{}cells", c.shape, c.backend, c.cells);
  fs::create_directories(dir);
  const fs::path log = dir / "talus.log";
  std::vector<std::string> args = {"run", case_file.string(), "--out", dir.string(), "--force"};
  args.push_back("--threads");
  args.push_back(std::to_string(options.threads)); // 0: the OpenMP default
  for (const auto& o : c.overrides) {
    args.push_back("--set");
    args.push_back(o);
  }
  std::vector<double> seconds;
  double peak = 0;
  nlohmann::json summary;
  try {
    for (int k = 0; k < options.repeats; ++k) {
      fs::remove(dir / "summary.json");
      const ChildResult r = spawn_and_wait(exe, args, log);
      peak = std::max(peak, r.max_rss_mb);
      if (r.exit_code != 0) {
        row.status = "failed";
        row.message = failure_message(log, r.exit_code);
        break;
      }
      summary = nlohmann::json::parse(read_text(dir / "summary.json"));
      seconds.push_back(json_number(summary, "wall_seconds"));
    }
    if (row.status.empty()) {
      row.error =
          case_name == "cantilever" ? cantilever_error(dir)
          : case_name == "cantilever_large"
              ? references::large_deflection_error(ResultsReader(dir / "run.h5"),
                                                   kLargeDeflectionAlpha)
          : case_name == "column_large_compression"
              ? references::compressed_column_errors(ResultsReader(dir / "run.h5"), kColumnRatio)
                    .raw
              : vibrating_bar_error(dir, c.cells);
      row.status = std::isfinite(row.error) ? "ok" : "failed";
      if (!std::isfinite(row.error))
        row.message = "error is not finite";
    }
  } catch (const std::exception& e) {
    row.status = "failed";
    row.message = e.what();
  }
  row.repeats = static_cast<int>(seconds.size());
  if (!seconds.empty()) {
    row.median_seconds = median(seconds);
    row.min_seconds = *std::min_element(seconds.begin(), seconds.end());
  }
  if (peak > 0)
    row.peak_rss_mb = peak;
  if (!summary.is_null()) {
    row.particles = json_number(summary, "particles");
    row.newton_iterations = json_number(summary, "newton_iterations");
    // Implicit: equations of the last Newton system; explicit: 2 velocity components per grid
    // node active at the last step.
    row.unknowns = c.backend == "explicit" ? 2.0 * json_number(summary, "active_nodes_last_step")
                                           : json_number(summary, "unknowns_last_step");
  }
  return row;
}

void write_csv(const fs::path& file, const std::string& case_name, const std::vector<Row>& rows) {
  std::ofstream out(file);
  if (!out)
    throw std::runtime_error("cannot create " + file.string());
  out << "case,shape,backend,cells,particles,unknowns,error,median_seconds,min_seconds,repeats,"
         "newton_iterations,peak_rss_mb,status,message\n";
  for (const auto& r : rows)
    out << fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n", case_name, r.config.shape,
                       r.config.backend, r.config.cells, csv_number(r.particles),
                       csv_number(r.unknowns), csv_number(r.error), csv_number(r.median_seconds),
                       csv_number(r.min_seconds), r.repeats, csv_number(r.newton_iterations),
                       csv_number(r.peak_rss_mb), r.status, csv_text(r.message));
}

void print_table(const std::string& case_name, const std::vector<Row>& rows, double baseline_mb,
                 int repeats, int threads) {
  fmt::print("work-precision: {} ({} repeats per configuration, {} OpenMP thread(s); seconds are "
             "run_case wall time; peak RSS per run, baseline of the binary {:.0f} MB)\n",
             case_name, repeats, threads > 0 ? std::to_string(threads) : "default", baseline_mb);
  fmt::print("{:<7} {:<15} {:>5} {:>9} {:>9} {:>10} {:>10} {:>10} {:>6} {:>8}  {}\n", "shape",
             "backend", "cells", "particles", "unknowns", "error", "median s", "min s", "newton",
             "RSS MB", "status");
  fmt::print("{}\n", std::string(107, '-'));
  for (const auto& r : rows)
    fmt::print("{:<7} {:<15} {:>5} {:>9} {:>9} {:>10} {:>10} {:>10} {:>6} {:>8}  {}{}\n",
               r.config.shape, r.config.backend, r.config.cells, cell(r.particles, "{:.0f}"),
               cell(r.unknowns, "{:.0f}"), cell(r.error, "{:.3e}"),
               cell(r.median_seconds, "{:.4f}"), cell(r.min_seconds, "{:.4f}"),
               cell(r.newton_iterations, "{:.0f}"), cell(r.peak_rss_mb, "{:.1f}"), r.status,
               r.message.empty() ? "" : " (" + r.message + ")");
}

} // namespace

std::vector<std::string> bench_cases() {
  return {"cantilever",    "cantilever_large",    "column_large_compression",
          "vibrating_bar", "explicit_throughput", "newton_cost",
          "fos_cost",      "strong_scaling"};
}

int run_bench(const BenchOptions& options) {
  const auto cases = bench_cases();
  if (std::find(cases.begin(), cases.end(), options.case_name) == cases.end())
    throw InputError({"--case", 0, 0, ""},
                     fmt::format("no work-precision benchmark for case '{}' (supported: {})",
                                 options.case_name, fmt::join(cases, ", ")));
  if (options.repeats < 3)
    throw InputError(
        {"--repeats", 0, 0, ""},
        fmt::format("at least 3 repeats are needed for a median (got {})", options.repeats));
  if (!options.baseline.empty() && options.case_name != "newton_cost" &&
      options.case_name != "explicit_throughput")
    throw InputError({"--vs", 0, 0, ""}, "only --case newton_cost and explicit_throughput "
                                         "compare with another binary");
  if (!options.baseline.empty() && !std::filesystem::is_regular_file(options.baseline))
    throw InputError({"--vs", 0, 0, ""},
                     fmt::format("'{}' is not a file", options.baseline.string()));
  if (options.case_name == "explicit_throughput")
    return run_throughput_bench(options);
  if (options.case_name == "newton_cost")
    return run_newton_cost_bench(options);
  if (options.case_name == "fos_cost")
    return run_fos_cost_bench(options);
  if (options.case_name == "strong_scaling")
    return run_scaling_bench(options);
  const fs::path data_dir = verification_dir();
  // The large-deflection beam is the cantilever scene with overrides (see sweep()).
  const std::string scene =
      options.case_name == "cantilever_large" ? "cantilever" : options.case_name;
  const fs::path case_file = data_dir / (scene + ".yaml");
  const fs::path plot_script = data_dir.parent_path() / "scripts" / "plot_bench.py";
  if (!fs::exists(case_file))
    throw std::runtime_error("verification scene not found: " + case_file.string());
  if (!fs::exists(plot_script))
    throw std::runtime_error("plot script not found: " + plot_script.string());
  // The children execute this very binary image (via /proc/self/exe, so a rebuild of the file
  // during a sweep does not mix binaries).
  const fs::path exe = "/proc/self/exe";
  const fs::path out =
      options.out_dir.empty() ? fs::path("results") / "bench" / options.case_name : options.out_dir;
  const fs::path runs = out / "runs";
  fs::create_directories(runs);

  // Fixed footprint of the binary (libraries, no scene): the floor under every RSS figure.
  const double baseline_mb = spawn_and_wait(exe, {"info"}, runs / "baseline.log").max_rss_mb;

  const auto configs = sweep(options.case_name, options.quick);
  std::vector<Row> rows;
  for (std::size_t i = 0; i < configs.size(); ++i) {
    const Config& c = configs[i];
    fmt::print(stderr, "bench [{}/{}] {} {} {} {} cells ... ", i + 1, configs.size(),
               options.case_name, c.shape, c.backend, c.cells);
    std::fflush(stderr);
    rows.push_back(run_configuration(options.case_name, c, options, exe, case_file, runs));
    const Row& r = rows.back();
    if (r.status == "ok")
      fmt::print(stderr, "error {:.3e}, median {:.4f} s, {} MB\n", r.error, r.median_seconds,
                 cell(r.peak_rss_mb, "{:.0f}"));
    else
      fmt::print(stderr, "FAILED: {}\n", r.message);
  }

  const fs::path csv = out / "bench.csv";
  write_csv(csv, options.case_name, rows);
  print_table(options.case_name, rows, baseline_mb, options.repeats, options.threads);

  plot_table(plot_script, csv, out / "bench.png");
  return kExitOk;
}

} // namespace talus
