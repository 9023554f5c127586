// `talus bench --case fos_cost`: the cost and the answer of each factor-of-safety mode on the
// Griffiths & Lane slope (cases/slope_griffiths_lane.yaml; include/talus/verify/bench.hpp).
//
// Measurement choices:
//  * Each search is a child `talus fos` process; the modes (independent trials with bisection,
//    and the incremental strength reduction) alternate repeat by repeat, so a noisy machine
//    slows both alike. The cost is fos.json's CPU and wall seconds of the search and its Newton
//    iterations; the answer is its bracket. Medians over the repeats; the ratio of each mode's
//    CPU to the trials' is the median of the repeat-by-repeat ratios.
#include "talus/verify/bench.hpp"

#include "child_process.hpp"

#include "talus/core/errors.hpp"
#include "talus/verify/verification.hpp"

#include <cmath>
#include <fmt/format.h>
#include <fstream>
#include <nlohmann/json.hpp>

namespace talus {

namespace fs = std::filesystem;
using namespace bench_detail;

namespace {

/// strength_reduction.mode values; the first is the reference of the CPU ratio.
const std::vector<std::string> kModes = {"trials", "incremental"};

struct FosCostRow {
  std::string mode;
  double lower = NAN, upper = NAN, factor_of_safety = NAN;
  double newton_iterations = NAN;
  int trials = 0;
  std::vector<double> cpu, wall, ratio;
  std::string status = "ok";
  std::string message;
};

void run_search(FosCostRow& row, const fs::path& case_file, const fs::path& dir, int threads,
                const fs::path& exe) {
  const fs::path log = dir / "talus.log";
  const ChildResult r =
      spawn_and_wait(exe,
                     {"fos", case_file.string(), "--out", dir.string(), "--force", "--threads",
                      std::to_string(threads), "--set", "strength_reduction.mode=" + row.mode},
                     log);
  if (r.exit_code != 0)
    throw std::runtime_error(failure_message(log, r.exit_code));
  const auto j = nlohmann::json::parse(read_text(dir / "fos.json"));
  if (!j.value("bracketed", false))
    throw std::runtime_error("no bracket: " + j.value("message", std::string()));
  row.lower = j.at("bracket")[0].get<double>();
  row.upper = j.at("bracket")[1].get<double>();
  row.factor_of_safety = j.at("factor_of_safety").get<double>();
  row.newton_iterations = j.at("newton_iterations").get<double>();
  row.trials = j.at("trials").get<int>();
  row.cpu.push_back(j.at("cpu_seconds").get<double>());
  row.wall.push_back(j.at("wall_seconds").get<double>());
}

} // namespace

int run_fos_cost_bench(const BenchOptions& options) {
  const fs::path case_file =
      verification_dir().parent_path() / "cases" / "slope_griffiths_lane.yaml";
  const fs::path exe = "/proc/self/exe";
  const fs::path out =
      options.out_dir.empty() ? fs::path("results") / "bench" / "fos_cost" : options.out_dir;
  std::vector<FosCostRow> rows;
  for (const auto& mode : kModes) {
    rows.emplace_back();
    rows.back().mode = mode;
  }
  for (int k = 0; k < options.repeats; ++k)
    for (auto& row : rows) {
      if (row.status != "ok")
        continue;
      fmt::print(stderr, "bench [{}/{}] {} ... ", k + 1, options.repeats, row.mode);
      std::fflush(stderr);
      const fs::path dir = out / "runs" / row.mode;
      fs::create_directories(dir);
      try {
        run_search(row, case_file, dir, options.threads, exe);
        if (rows.front().cpu.size() == row.cpu.size()) // the trials' search of this repeat
          row.ratio.push_back(row.cpu.back() / rows.front().cpu.back());
        fmt::print(stderr, "FoS {:.4f}, {:.1f} s CPU\n", row.factor_of_safety, row.cpu.back());
      } catch (const std::exception& e) {
        row.status = "failed";
        row.message = e.what();
        fmt::print(stderr, "FAILED: {}\n", row.message);
      }
    }

  const fs::path csv = out / "fos_cost.csv";
  std::ofstream file(csv);
  if (!file)
    throw std::runtime_error("cannot create " + csv.string());
  file << "mode,lower,upper,factor_of_safety,trials,newton_iterations,median_cpu_seconds,"
          "median_wall_seconds,cpu_ratio_to_trials,repeats,status,message\n";
  fmt::print("factor-of-safety search cost on {} ({} repeats, modes alternating, {} thread(s); "
             "CPU and wall of the search from fos.json, medians)\n",
             case_file.filename().string(), options.repeats, options.threads);
  fmt::print("{:<12} {:>17} {:>8} {:>7} {:>7} {:>8} {:>8} {:>10}  {}\n", "mode", "bracket", "FoS",
             "trials", "newton", "CPU s", "wall s", "CPU ratio", "status");
  fmt::print("{}\n", std::string(96, '-'));
  for (const auto& r : rows) {
    const auto med = [](const std::vector<double>& v) { return v.empty() ? NAN : median(v); };
    file << fmt::format("{},{},{},{},{},{},{},{},{},{},{},\"{}\"\n", r.mode, csv_number(r.lower),
                        csv_number(r.upper), csv_number(r.factor_of_safety), r.trials,
                        csv_number(r.newton_iterations), csv_number(med(r.cpu)),
                        csv_number(med(r.wall)), csv_number(med(r.ratio)), r.cpu.size(), r.status,
                        r.message);
    fmt::print("{:<12} {:>17} {:>8} {:>7} {:>7} {:>8} {:>8} {:>10}  {}{}\n", r.mode,
               std::isfinite(r.lower) ? fmt::format("[{:.4f}, {:.4f}]", r.lower, r.upper) : "-",
               cell(r.factor_of_safety, "{:.4f}"), r.trials, cell(r.newton_iterations, "{:.0f}"),
               cell(med(r.cpu), "{:.2f}"), cell(med(r.wall), "{:.2f}"),
               cell(med(r.ratio), "{:.3f}"), r.status,
               r.message.empty() ? "" : " (" + r.message + ")");
  }
  fmt::print("\nwrote {}\n", csv.string());
  return kExitOk;
}

} // namespace talus
