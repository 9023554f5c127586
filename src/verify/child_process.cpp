// Child processes of the benchmarks (see child_process.hpp).
#include "child_process.hpp"

#include "talus/verify/verification.hpp"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <fcntl.h>
#include <fmt/format.h>
#include <fstream>
#include <spawn.h>
#include <sstream>
#include <stdexcept>
#include <sys/resource.h>
#include <sys/wait.h>

extern char** environ;

namespace talus::bench_detail {

namespace fs = std::filesystem;

ChildResult spawn_and_wait(const fs::path& program, const std::vector<std::string>& args,
                           const fs::path& log) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  std::vector<std::string> argv_text = {program.string()};
  argv_text.insert(argv_text.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : argv_text)
    argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  const auto start = std::chrono::steady_clock::now();
  const int rc = posix_spawn(&pid, program.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0)
    throw std::runtime_error(
        fmt::format("cannot start '{}': {}", program.string(), std::strerror(rc)));
  int status = 0;
  struct rusage usage {};
  while (wait4(pid, &status, 0, &usage) < 0)
    if (errno != EINTR)
      throw std::runtime_error(fmt::format("wait4 failed: {}", std::strerror(errno)));
  ChildResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  r.max_rss_mb = static_cast<double>(usage.ru_maxrss) / 1024.0;
  r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const auto seconds = [](const timeval& t) { return t.tv_sec + 1e-6 * t.tv_usec; };
  r.cpu_seconds = seconds(usage.ru_utime) + seconds(usage.ru_stime);
  return r;
}

std::string read_text(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void plot_table(const fs::path& script, const fs::path& csv, const fs::path& png) {
  const fs::path log = csv.parent_path() / "plot.log";
  const ChildResult plot =
      spawn_and_wait("/usr/bin/python3", {script.string(), csv.string(), png.string()}, log);
  if (plot.exit_code != 0)
    throw std::runtime_error(
        fmt::format("{} failed (exit {}):\n{}", script.string(), plot.exit_code, read_text(log)));
  fmt::print("\nwrote {} and {}\n", csv.string(), png.string());
}

std::string failure_message(const fs::path& log, int exit_code) {
  std::istringstream in(read_text(log));
  std::string line, last, last_talus;
  while (std::getline(in, line)) {
    if (line.empty())
      continue;
    last = line;
    if (line.rfind("talus: ", 0) == 0)
      last_talus = line.substr(7);
  }
  const std::string text = !last_talus.empty() ? last_talus : last;
  return fmt::format("exit {}{}{}", exit_code, text.empty() ? "" : ": ", text);
}

double json_number(const nlohmann::json& j, const std::string& key) {
  return j.contains(key) && j[key].is_number() ? j[key].get<double>() : NAN;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::string csv_number(double v) {
  return std::isfinite(v) ? fmt::format("{:.6g}", v) : "";
}

std::string cell(double v, const char* format) {
  return std::isfinite(v) ? fmt::format(fmt::runtime(format), v) : "-";
}

std::vector<std::string> refined_run_args(const RefinedScene& scene,
                                          const std::filesystem::path& dir, int threads) {
  std::vector<std::string> args = {"run",
                                   (verification_dir() / (scene.scene + ".yaml")).string(),
                                   "--out",
                                   dir.string(),
                                   "--force",
                                   "--threads",
                                   std::to_string(threads),
                                   "--set",
                                   fmt::format("grid.cell_size={:g}", scene.cell_size),
                                   "--set",
                                   fmt::format("time.end_time={:g}", scene.end_time),
                                   "--set",
                                   "output.every_time=1"};
  for (const std::string& o : scene.overrides) {
    args.push_back("--set");
    args.push_back(o);
  }
  return args;
}

} // namespace talus::bench_detail
