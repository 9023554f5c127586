// `talus bench --case explicit_throughput`: the explicit step's particle-steps per second
// against the number of points, the threads and the dimension (include/talus/verify/bench.hpp).
//
// Measurement choices:
//  * The scenes are the verification colliding discs (2D) and spheres (3D), refined by the cell
//    size at two points per cell and direction, GIMP, MUSL, neo-Hookean, run over the approach
//    (before the bodies touch and while they do), one frame at each end.
//  * The time is the stepping loop's own (summary.json "seconds_stepping": without building the
//    scene or writing frames); the figure is points x steps / that time, the median over the
//    repeats. Each run is a child process, so its peak resident set is its own.
//  * Memory per point: the run's peak resident set less the binary's own (`talus info`),
//    divided by the points; it includes the active grid nodes, which grow with the points.
//  * The energy drift |E(end) - E(0)| / E(0) (kinetic plus strain) says the run was sound.
//  * `--vs OLD_TALUS` runs an older binary on the same configuration before each repeat and
//    reports the median ratio of whole-process wall times (an older binary may not report
//    the stepping loop's own time).
#include "talus/verify/bench.hpp"

#include "child_process.hpp"

#include "talus/core/errors.hpp"
#include "talus/io/csv.hpp"
#include "talus/verify/verification.hpp"

#include <cmath>
#include <fmt/format.h>
#include <fstream>
#include <nlohmann/json.hpp>

namespace talus {

namespace fs = std::filesystem;
using namespace bench_detail;

namespace {

struct ThroughputConfig : RefinedScene {
  int threads = 1;
};

struct ThroughputRow {
  ThroughputConfig config;
  double particles = NAN;
  double steps = NAN;
  double active_nodes = NAN;
  double median_rate = NAN; ///< particle-steps per second
  double min_rate = NAN;
  int repeats = 0;
  double peak_rss_mb = NAN;
  double bytes_per_point = NAN;
  double energy_drift = NAN;
  double ratio_to_baseline = NAN; ///< median of the repeats' this / --vs whole-process times
  std::string status = "ok";
  std::string message;
};

std::vector<ThroughputConfig> throughput_sweep(bool quick) {
  std::vector<ThroughputConfig> configs;
  // 2D: 2.5k, 10k, 40k and 160k points; 3D: 4.3k and 34.5k.
  std::vector<double> discs = {0.02, 0.01, 0.005, 0.0025};
  if (quick)
    discs.pop_back();
  for (const int threads : {1, 2}) {
    for (const double h : discs)
      configs.push_back({{"colliding_discs", 2, h, 0.02}, threads});
    for (const double h : {0.05, 0.025})
      configs.push_back({{"colliding_spheres", 3, h, 0.01}, threads});
  }
  return configs;
}

double energy_drift(const fs::path& series_file) {
  const CsvTable series = read_csv(series_file);
  const auto& kinetic = series.column("kinetic_energy");
  const auto& strain = series.column("strain_energy");
  const double first = kinetic.front() + strain.front();
  return std::abs(kinetic.back() + strain.back() - first) / first;
}

ThroughputRow run_throughput(const ThroughputConfig& c, const BenchOptions& options,
                             double baseline_mb, const fs::path& exe, const fs::path& runs_dir) {
  const int repeats = options.repeats;
  ThroughputRow row;
  row.config = c;
  const fs::path dir = runs_dir / fmt::format("{}_h{:g}_t{}", c.scene, c.cell_size, c.threads);
  fs::create_directories(dir);
  const fs::path log = dir / "talus.log";
  const std::vector<std::string> args = refined_run_args(c, dir, c.threads);
  std::vector<double> rates, ratios;
  double peak = 0;
  try {
    for (int k = 0; k < repeats; ++k) {
      double old_seconds = NAN;
      if (!options.baseline.empty()) {
        auto old_args = args;
        old_args[3] = (dir / "baseline").string(); // --out
        const ChildResult old = spawn_and_wait(options.baseline, old_args, dir / "baseline.log");
        if (old.exit_code != 0)
          throw std::runtime_error("--vs binary: " +
                                   failure_message(dir / "baseline.log", old.exit_code));
        old_seconds = old.wall_seconds;
      }
      fs::remove(dir / "summary.json");
      const ChildResult r = spawn_and_wait(exe, args, log);
      if (std::isfinite(old_seconds))
        ratios.push_back(r.wall_seconds / old_seconds);
      peak = std::max(peak, r.max_rss_mb);
      if (r.exit_code != 0) {
        row.status = "failed";
        row.message = failure_message(log, r.exit_code);
        break;
      }
      const auto summary = nlohmann::json::parse(read_text(dir / "summary.json"));
      row.particles = json_number(summary, "particles");
      row.steps = json_number(summary, "steps_stepping");
      row.active_nodes = json_number(summary, "active_nodes_last_step");
      rates.push_back(row.particles * row.steps / json_number(summary, "seconds_stepping"));
    }
    if (row.status == "ok")
      row.energy_drift = energy_drift(dir / "timeseries.csv");
  } catch (const std::exception& e) {
    row.status = "failed";
    row.message = e.what();
  }
  row.repeats = static_cast<int>(rates.size());
  if (!ratios.empty())
    row.ratio_to_baseline = median(ratios);
  if (!rates.empty()) {
    row.median_rate = median(rates);
    row.min_rate = *std::min_element(rates.begin(), rates.end());
  }
  if (peak > 0) {
    row.peak_rss_mb = peak;
    row.bytes_per_point = (peak - baseline_mb) * 1024.0 * 1024.0 / row.particles;
  }
  return row;
}

void write_throughput_csv(const fs::path& file, const std::vector<ThroughputRow>& rows) {
  std::ofstream out(file);
  if (!out)
    throw std::runtime_error("cannot create " + file.string());
  out << "scene,dimension,cell_size,threads,particles,steps,active_nodes,"
         "median_particle_steps_per_second,min_particle_steps_per_second,repeats,peak_rss_mb,"
         "bytes_per_point,energy_drift,ratio_to_baseline,status,message\n";
  for (const auto& r : rows)
    out << fmt::format(
        "{},{},{:g},{},{},{},{},{},{},{},{},{},{},{},{},\"{}\"\n", r.config.scene,
        r.config.dimension, r.config.cell_size, r.config.threads, csv_number(r.particles),
        csv_number(r.steps), csv_number(r.active_nodes), csv_number(r.median_rate),
        csv_number(r.min_rate), r.repeats, csv_number(r.peak_rss_mb), csv_number(r.bytes_per_point),
        csv_number(r.energy_drift), csv_number(r.ratio_to_baseline), r.status, r.message);
}

void print_throughput_table(const std::vector<ThroughputRow>& rows, double baseline_mb,
                            int repeats) {
  fmt::print("explicit throughput ({} repeats per configuration; rate = points x steps / the "
             "stepping loop's wall time, median; memory: peak RSS less the binary's {:.0f} MB)\n",
             repeats, baseline_mb);
  fmt::print("{:<18} {:>3} {:>8} {:>7} {:>9} {:>6} {:>8} {:>12} {:>9} {:>9} {:>9} {:>7}  {}\n",
             "scene", "dim", "h", "threads", "particles", "steps", "nodes", "M pt-steps/s",
             "RSS MB", "B/point", "E drift", "vs old", "status");
  fmt::print("{}\n", std::string(126, '-'));
  for (const auto& r : rows)
    fmt::print("{:<18} {:>3} {:>8g} {:>7} {:>9} {:>6} {:>8} {:>12} {:>9} {:>9} {:>9} {:>7}  {}{}\n",
               r.config.scene, r.config.dimension, r.config.cell_size, r.config.threads,
               cell(r.particles, "{:.0f}"), cell(r.steps, "{:.0f}"), cell(r.active_nodes, "{:.0f}"),
               cell(r.median_rate / 1e6, "{:.2f}"), cell(r.peak_rss_mb, "{:.0f}"),
               cell(r.bytes_per_point, "{:.0f}"), cell(r.energy_drift, "{:.1e}"),
               cell(r.ratio_to_baseline, "{:.3f}"), r.status,
               r.message.empty() ? "" : " (" + r.message + ")");
}

} // namespace

int run_throughput_bench(const BenchOptions& options) {
  const fs::path plot_script = verification_dir().parent_path() / "scripts" / "plot_throughput.py";
  if (!fs::exists(plot_script))
    throw std::runtime_error("plot script not found: " + plot_script.string());
  const fs::path exe = "/proc/self/exe";
  const fs::path out = options.out_dir.empty()
                           ? fs::path("results") / "bench" / "explicit_throughput"
                           : options.out_dir;
  const fs::path runs = out / "runs";
  fs::create_directories(runs);
  const double baseline_mb = spawn_and_wait(exe, {"info"}, runs / "baseline.log").max_rss_mb;

  const auto configs = throughput_sweep(options.quick);
  std::vector<ThroughputRow> rows;
  for (std::size_t i = 0; i < configs.size(); ++i) {
    const ThroughputConfig& c = configs[i];
    fmt::print(stderr, "bench [{}/{}] {} h = {:g}, {} thread(s) ... ", i + 1, configs.size(),
               c.scene, c.cell_size, c.threads);
    std::fflush(stderr);
    rows.push_back(run_throughput(c, options, baseline_mb, exe, runs));
    const ThroughputRow& r = rows.back();
    if (r.status == "ok")
      fmt::print(stderr, "{:.0f} points, {:.2f} M particle-steps/s\n", r.particles,
                 r.median_rate / 1e6);
    else
      fmt::print(stderr, "FAILED: {}\n", r.message);
  }
  const fs::path csv = out / "throughput.csv";
  write_throughput_csv(csv, rows);
  print_throughput_table(rows, baseline_mb, options.repeats);

  plot_table(plot_script, csv, out / "throughput.png");
  return kExitOk;
}

} // namespace talus
