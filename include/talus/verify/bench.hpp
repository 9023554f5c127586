#pragma once
// `talus bench`: the work-precision runner. For a verification case it sweeps resolution x shape
// function x linear backend, repeats every configuration, and writes bench.csv (error against
// the case's analytical reference, median/min wall seconds of run_case, Newton iterations, peak
// resident memory) plus bench.png (log-log error against median seconds, scripts/plot_bench.py).
//
// Every run is a child process `talus run <verification/case.yaml> --set ...` so that its peak
// resident set size (ru_maxrss from wait4) belongs to that run alone; the wall time is the
// child's own run_case time (summary.json "wall_seconds"), so process start-up is not counted.
//
// `--case explicit_throughput` is the explicit step's speed instead (throughput_bench.cpp):
// particle-steps per second of the stepping loop against points, threads and dimension, with
// the memory per point, into throughput.csv and throughput.png. `--case newton_cost`
// (newton_cost_bench.cpp) is an implicit Newton iteration's cost by phase against a bare
// factorisation + solve of its own tangent (Google Benchmark), with memory per point, in 2D and
// 3D, optionally side by side with an older binary (`--vs`). `--case fos_cost`
// (fos_cost_bench.cpp) is the CPU and the bracket of each factor-of-safety mode.
// `--case strong_scaling` (scaling_bench.cpp) is a distributed explicit run on two ranks
// against the serial run on one and on two threads: speed-up, efficiency, communication share.
#include <filesystem>
#include <string>
#include <vector>

namespace talus {

struct BenchOptions {
  std::string case_name;         ///< one of bench_cases()
  std::filesystem::path out_dir; ///< empty: results/bench/<case>
  int repeats = 3;               ///< runs per configuration; at least 3
  bool quick = false;            ///< drop the finest resolution
  /// OpenMP threads of each run; 0 keeps the OpenMP default (all cores). The default 1 keeps
  /// timings comparable on a shared machine: with more threads than idle cores, OpenMP
  /// barriers wait on descheduled threads and small runs slow down by an order of magnitude.
  int threads = 1;
  /// `--vs`: an older talus binary run alternately with this one (newton_cost and
  /// explicit_throughput).
  std::filesystem::path baseline;
};

/// The cases `talus bench --case` accepts.
std::vector<std::string> bench_cases();

/// Runs the sweep, prints the table, writes bench.csv and bench.png; returns the exit code
/// (0 when the sweep ran, even if single configurations failed: they are rows with status
/// "failed"). Throws InputError for an unknown case or repeats < 3, std::runtime_error when the
/// plot script fails.
int run_bench(const BenchOptions& options);

/// `--case explicit_throughput` (called by run_bench; options.threads is not used: the threads
/// are part of the sweep).
int run_throughput_bench(const BenchOptions& options);

/// `--case newton_cost` (called by run_bench).
int run_newton_cost_bench(const BenchOptions& options);

/// `--case fos_cost` (called by run_bench).
int run_fos_cost_bench(const BenchOptions& options);

/// `--case strong_scaling` (called by run_bench): serial on one thread, mpirun -np 2, serial
/// on two threads, for a 2D and a 3D explicit case (scaling_bench.cpp).
int run_scaling_bench(const BenchOptions& options);

} // namespace talus
