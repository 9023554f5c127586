#pragma once
// Child runs of the benchmarks: `talus run ...` as its own process, so that its peak resident
// set (ru_maxrss from wait4) belongs to that run alone, and what the benchmarks read back.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace talus::bench_detail {

struct ChildResult {
  int exit_code = 0;
  double max_rss_mb = 0;
  double wall_seconds = 0; ///< from spawn to exit: the whole process, start-up included
  double cpu_seconds = 0;  ///< user + system time of the child (ru_utime + ru_stime)
};

/// Runs `program args...` with stdout and stderr into `log`; returns its exit code (128 +
/// signal when killed), its peak resident set (ru_maxrss, KiB on Linux), its wall and CPU time.
ChildResult spawn_and_wait(const std::filesystem::path& program,
                           const std::vector<std::string>& args, const std::filesystem::path& log);

std::string read_text(const std::filesystem::path& file);

/// Draws `csv` into `png` with `/usr/bin/python3 script csv png` (its output into plot.log
/// beside the csv) and says where both are; throws std::runtime_error with that output when
/// the script fails.
void plot_table(const std::filesystem::path& script, const std::filesystem::path& csv,
                const std::filesystem::path& png);

/// The child's error message: its last "talus: ..." line, else its last non-empty line.
std::string failure_message(const std::filesystem::path& log, int exit_code);

double median(std::vector<double> v);

/// The number j[key] (summary.json, fos.json), NaN when it is missing or not a number.
double json_number(const nlohmann::json& j, const std::string& key);

/// A verification scene refined for a speed measurement (explicit_throughput, strong_scaling).
struct RefinedScene {
  std::string scene; ///< a verification case file's stem
  int dimension = 2;
  double cell_size = 0;
  double end_time = 0;
  std::vector<std::string> overrides{}; ///< further `--set` KEY=VALUE
};

/// `run <scene> --out dir --force --threads N` at the scene's cell size and end time, with
/// frames only at the ends.
std::vector<std::string> refined_run_args(const RefinedScene& scene,
                                          const std::filesystem::path& dir, int threads);

/// `format` of v, or "-" when v is not finite (table cells).
std::string cell(double v, const char* format);

/// A CSV field: v with 6 significant digits, empty when not finite.
std::string csv_number(double v);

} // namespace talus::bench_detail
