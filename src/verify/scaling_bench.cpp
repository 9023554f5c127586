// `talus bench --case strong_scaling`: a distributed run on this machine's cores against the
// serial run (include/talus/verify/bench.hpp).
//
// Measurement choices:
//  * Explicit: the scenes of explicit_throughput at its largest sizes that run in seconds: the
//    colliding discs (2D, 40k points) and spheres (3D, 34.5k points), GIMP, MUSL, run through
//    their contact, which the cut between the ranks crosses.
//  * Implicit: the cantilever (2D, 32 cells through the depth, 32.8k points) and the 3D one
//    (8 cells, 32.8k points), one linear-elastic load step. Every mode solves with Belos CG and
//    MueLu, the distributed run's solver, so the ratios compare one algorithm on one and two
//    processes; the case's own direct solver (CHOLMOD) is timed beside them as a fourth row.
//  * Three runs per repeat, alternating so that a drift of the machine's speed falls on all
//    three: serial on one thread (np = 1), `mpirun -np 2` with one thread per rank (np = 2),
//    and serial on two threads (OpenMP on the same two cores, for comparison).
//  * The time is the stepping loop's own (summary.json "seconds_stepping", rank 0's), the
//    median over the repeats; speed-up = np 1 / np 2, efficiency = speed-up / 2. The
//    communication share is the largest time a rank spent in MPI calls (waiting for the other
//    included: "seconds_communication_max") over the stepping time. Whole-process wall and CPU
//    seconds are the children's own.
//  * The results of the np = 2 run are compared with the serial run's (largest relative
//    difference of the final frame's positions), so a fast wrong run cannot pass unnoticed.
#include "child_process.hpp"
#include "talus/core/errors.hpp"
#include "talus/io/csv.hpp"
#include "talus/io/results.hpp"
#include "talus/parallel/communicator.hpp"
#include "talus/verify/bench.hpp"
#include "talus/verify/verification.hpp"

#include <cmath>
#include <fmt/format.h>
#include <fstream>

namespace talus {

namespace fs = std::filesystem;
using namespace bench_detail;

namespace {

struct ScalingConfig {
  RefinedScene scene;
  /// Implicit scenes: the linear solver of every mode but the direct one (the distributed
  /// run's); empty for the explicit scenes.
  std::string solver;
};

/// One way of running a configuration.
struct Mode {
  std::string name;
  int ranks = 1;
  int threads = 1;
};

/// The implicit scenes' extra mode: serial with the case's own linear solver.
const Mode kDirect = {"serial, 1 thread, direct", 1, 1};

struct ScalingRow {
  ScalingConfig config;
  Mode mode;
  bool baseline = false; ///< the row the others' speed-up is against (serial, 1 thread)
  double particles = NAN;
  double steps = NAN;
  double stepping_seconds = NAN; ///< median
  double wall_seconds = NAN;     ///< median, whole process (mpirun included)
  double cpu_seconds = NAN;      ///< median, all ranks
  double communication_share = NAN;
  double peak_rss_mb = NAN; ///< the largest process's (a rank's; mpirun's is smaller)
  double migrated = NAN;
  double difference = NAN; ///< final positions against the serial run, relative to the extent
  std::string status = "ok";
  std::string message;
};

const std::vector<Mode> kModes = {
    {"serial, 1 thread", 1, 1}, {"mpirun -np 2, 1 thread each", 2, 1}, {"serial, 2 threads", 1, 2}};

/// The largest |a - b| of the final frame's positions over the largest |a|.
double final_difference(const fs::path& a_dir, const fs::path& b_dir) {
  const ResultsReader a(a_dir / "run.h5"), b(b_dir / "run.h5");
  Index rows = 0, cols = 0;
  const auto x = a.read(a.frame_count() - 1, "position", &rows, &cols);
  const auto y = b.read(b.frame_count() - 1, "position", &rows, &cols);
  if (x.size() != y.size())
    return INFINITY;
  double diff = 0, scale = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    diff = std::max(diff, std::abs(x[i] - y[i]));
    scale = std::max(scale, std::abs(x[i]));
  }
  return diff / scale;
}

/// The modes a configuration runs in: kModes, and for an implicit scene kDirect too.
std::vector<Mode> modes_of(const ScalingConfig& c) {
  std::vector<Mode> modes = kModes;
  if (!c.solver.empty())
    modes.push_back(kDirect);
  return modes;
}

/// Where mode i of configuration `tag` runs.
fs::path run_dir(const fs::path& runs_dir, const std::string& tag, std::size_t i) {
  return runs_dir / fmt::format("{}_mode{}", tag, i);
}

std::vector<ScalingRow> run_config(const ScalingConfig& c, const BenchOptions& options,
                                   const fs::path& exe, const fs::path& mpirun,
                                   const fs::path& runs_dir) {
  const std::vector<Mode> modes = modes_of(c);
  std::vector<ScalingRow> rows;
  std::vector<std::vector<double>> stepping(modes.size()), wall(modes.size()), cpu(modes.size()),
      share(modes.size()), rss(modes.size());
  for (const Mode& m : modes) {
    ScalingRow row;
    row.config = c;
    row.mode = m;
    row.baseline = rows.empty();
    rows.push_back(row);
  }
  const std::string tag = fmt::format("{}_h{:g}", c.scene.scene, c.scene.cell_size);
  try {
    for (int k = 0; k < options.repeats; ++k)
      for (std::size_t i = 0; i < modes.size(); ++i) {
        const Mode& m = modes[i];
        const fs::path dir = run_dir(runs_dir, tag, i);
        RefinedScene scene = c.scene;
        if (!c.solver.empty() && m.name != kDirect.name)
          scene.overrides.push_back("solver.linear_solver=" + c.solver);
        std::vector<std::string> args = refined_run_args(scene, dir, m.threads);
        fs::create_directories(dir);
        fs::remove(dir / "summary.json");
        ChildResult r;
        if (m.ranks > 1) {
          args.insert(args.begin(), {"-np", std::to_string(m.ranks), "--oversubscribe", "--bind-to",
                                     "none", exe.string()});
          r = spawn_and_wait(mpirun, args, runs_dir / (tag + ".log"));
        } else {
          r = spawn_and_wait(exe, args, runs_dir / (tag + ".log"));
        }
        if (r.exit_code != 0)
          throw std::runtime_error(fmt::format(
              "{}: {}", m.name, failure_message(runs_dir / (tag + ".log"), r.exit_code)));
        const auto summary = nlohmann::json::parse(read_text(dir / "summary.json"));
        ScalingRow& row = rows[i];
        row.particles = json_number(summary, "particles");
        row.steps = json_number(summary, "steps_stepping");
        const double seconds = json_number(summary, "seconds_stepping");
        stepping[i].push_back(seconds);
        wall[i].push_back(r.wall_seconds);
        rss[i].push_back(r.max_rss_mb);
        cpu[i].push_back(r.cpu_seconds);
        if (m.ranks > 1) {
          share[i].push_back(json_number(summary, "seconds_communication_max") / seconds);
          row.migrated = json_number(summary, "points_migrated");
        }
      }
    const fs::path serial = run_dir(runs_dir, tag, 0);
    for (std::size_t i = 0; i < modes.size(); ++i) {
      ScalingRow& row = rows[i];
      row.stepping_seconds = median(stepping[i]);
      row.wall_seconds = median(wall[i]);
      row.cpu_seconds = median(cpu[i]);
      row.peak_rss_mb = median(rss[i]);
      if (!share[i].empty())
        row.communication_share = median(share[i]);
      row.difference = final_difference(serial, run_dir(runs_dir, tag, i));
    }
  } catch (const std::exception& e) {
    for (auto& row : rows) {
      row.status = "failed";
      row.message = e.what();
    }
  }
  return rows;
}

/// The linear solver a row's runs used: empty for an explicit scene, the case's own for the
/// direct mode.
std::string linear_solver_of(const ScalingRow& r) {
  if (r.config.solver.empty())
    return "";
  return r.mode.name == kDirect.name ? "case's own" : r.config.solver;
}

void write_csv(const fs::path& file, const std::vector<ScalingRow>& rows) {
  std::ofstream out(file);
  if (!out)
    throw std::runtime_error("cannot create " + file.string());
  out << "scene,dimension,cell_size,linear_solver,mode,ranks,threads,particles,steps,"
         "stepping_seconds,"
         "speed_up,efficiency,wall_seconds,cpu_seconds,peak_rss_mb,communication_share,points_"
         "migrated,"
         "difference_to_serial,status,message\n";
  double serial = NAN;
  for (const auto& r : rows) {
    if (r.baseline)
      serial = r.stepping_seconds;
    const double speed_up = serial / r.stepping_seconds;
    const int cores = r.mode.ranks * r.mode.threads;
    out << fmt::format("{},{},{:g},{},\"{}\",{},{},{},{},{},{},{},{},{},{},{},{},{},{},\"{}\"\n",
                       r.config.scene.scene, r.config.scene.dimension, r.config.scene.cell_size,
                       linear_solver_of(r), r.mode.name, r.mode.ranks, r.mode.threads,
                       csv_number(r.particles), csv_number(r.steps), csv_number(r.stepping_seconds),
                       csv_number(speed_up), csv_number(speed_up / cores),
                       csv_number(r.wall_seconds), csv_number(r.cpu_seconds),
                       csv_number(r.peak_rss_mb), csv_number(r.communication_share),
                       csv_number(r.migrated), csv_number(r.difference), r.status, r.message);
  }
}

void print_table(const std::vector<ScalingRow>& rows, int repeats) {
  fmt::print("strong scaling ({} repeats, alternating; time = the stepping loop's, median; "
             "speed-up and efficiency against serial on one thread)\n",
             repeats);
  fmt::print("{:<18} {:>3} {:>8} {:<28} {:>9} {:>6} {:>9} {:>8} {:>6} {:>8} {:>8} {:>7} {:>6} "
             "{:>9}  {}\n",
             "scene", "dim", "h", "mode", "particles", "steps", "step s", "speed-up", "eff.",
             "wall s", "CPU s", "RSS MB", "comm", "vs serial", "status");
  fmt::print("{}\n", std::string(148, '-'));
  double serial = NAN;
  for (const auto& r : rows) {
    if (r.baseline)
      serial = r.stepping_seconds;
    const double speed_up = serial / r.stepping_seconds;
    fmt::print(
        "{:<18} {:>3} {:>8g} {:<28} {:>9} {:>6} {:>9} {:>8} {:>6} {:>8} {:>8} {:>7} {:>6} "
        "{:>9}  {}{}\n",
        r.config.scene.scene, r.config.scene.dimension, r.config.scene.cell_size, r.mode.name,
        cell(r.particles, "{:.0f}"), cell(r.steps, "{:.0f}"), cell(r.stepping_seconds, "{:.3f}"),
        cell(speed_up, "{:.2f}"), cell(speed_up / (r.mode.ranks * r.mode.threads), "{:.2f}"),
        cell(r.wall_seconds, "{:.2f}"), cell(r.cpu_seconds, "{:.2f}"),
        cell(r.peak_rss_mb, "{:.0f}"), cell(100 * r.communication_share, "{:.0f}%"),
        cell(r.difference, "{:.1e}"), r.status, r.message.empty() ? "" : " (" + r.message + ")");
  }
}

} // namespace

int run_scaling_bench(const BenchOptions& options) {
  const fs::path exe = fs::read_symlink("/proc/self/exe");
  const fs::path mpirun = mpirun_for_children();
  const fs::path out =
      options.out_dir.empty() ? fs::path("results") / "bench" / "strong_scaling" : options.out_dir;
  const fs::path runs = out / "runs";
  fs::create_directories(runs);
  // Run through the contact, which the cut between the two ranks crosses: the ranks then share
  // the nodes of the contact zone.
  std::vector<ScalingConfig> configs = {{{"colliding_discs", 2, 0.005, 0.05}, ""},
                                        {{"colliding_spheres", 3, 0.025, 0.03}, ""},
                                        {{"cantilever", 2, 0.03125, 1.0}, "trilinos_cg"},
                                        {{"cantilever_3d", 3, 0.125, 1.0}, "trilinos_cg"}};
  if (options.quick)
    configs = {{{"colliding_discs", 2, 0.01, 0.05}, ""},
               {{"colliding_spheres", 3, 0.05, 0.03}, ""},
               {{"cantilever", 2, 0.0625, 1.0}, "trilinos_cg"},
               {{"cantilever_3d", 3, 0.25, 1.0}, "trilinos_cg"}};
  std::vector<ScalingRow> rows;
  for (const auto& c : configs) {
    fmt::print(stderr, "bench {} h = {:g} ...\n", c.scene.scene, c.scene.cell_size);
    const auto r = run_config(c, options, exe, mpirun, runs);
    rows.insert(rows.end(), r.begin(), r.end());
  }
  write_csv(out / "scaling.csv", rows);
  print_table(rows, options.repeats);
  fmt::print("table: {}\n", (out / "scaling.csv").string());
  return kExitOk;
}

} // namespace talus
