// talus_fuzz_case_reader: a seeded mutation fuzzer of the case reader. It mutates the shipped
// cases (cases/*.yaml, verification/*.yaml) with byte flips, token swaps, deleted, duplicated and
// swapped lines, numbers replaced by extremes (0, -1, 1e308, nan, ...), huge strings, deep
// nesting, YAML tags and stray YAML syntax, and feeds each mutant (sometimes with --set
// overrides) to read_case_text and, when it parses and its memory estimate is small, to
// build_scene in the case's dimension (2D, axisymmetric or 3D). A valid mutant whose scene is
// smaller still is stepped: run_case carries it for a few steps (explicit, implicit or staged,
// whatever it declares) into a scratch directory, and must end "stopped" (after those steps),
// "completed" or "numerical_failure", or refuse it with InputError.
//
// A failure is any exception other than InputError (the CLI maps it to exit 1), a crash (signal)
// or an input that takes longer than the watchdog (default 5 s): the input is saved to
// <crash-dir>/fuzz-<kind>-<seed>-<n>.yaml and the driver exits 1. Every --cli-every-th mutant also
// goes through the real binary (`talus check`), whose exit code must be 0, 2 or 3 (1 is an
// uncaught error).
//
//   talus_fuzz_case_reader --seconds 30 --seed 1 [--talus build/talus] [--crash-dir DIR]
//   talus_fuzz_case_reader --replay saved.yaml        (one input, as the loop would run it,
//                                                     with saved.yaml.set's overrides)
#include "talus/core/errors.hpp"
#include "talus/io/case_reader.hpp"
#include "talus/scene/memory_estimate.hpp"
#include "talus/scene/scene.hpp"
#include "talus/solver/run.hpp"

#include "case_mutator.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

// --- what the signal handler and the watchdog need --------------------------------------------
const std::string* g_input = nullptr; // the input being read
std::vector<std::string> g_sets;      // its --set overrides (written before it is read)
char g_crash_path[4096] = {};         // where a crash saves it
std::atomic<long long> g_started_ns{0};
std::atomic<bool> g_busy{false};

void write_all(int fd, const char* data, std::size_t size) {
  while (size > 0) {
    const ssize_t n = ::write(fd, data, size);
    if (n <= 0)
      return;
    data += n;
    size -= static_cast<std::size_t>(n);
  }
}

extern "C" void on_crash(int sig) {
  // Only async-signal-safe calls: open, write, close, then the default action.
  if (g_input != nullptr) {
    const int fd = ::open(g_crash_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) {
      write_all(fd, g_input->data(), g_input->size());
      ::close(fd);
    }
  }
  const char msg[] = "fuzz: CRASH (signal); the input is saved to ";
  write_all(2, msg, sizeof msg - 1);
  write_all(2, g_crash_path, std::strlen(g_crash_path));
  write_all(2, "\n", 1);
  ::signal(sig, SIG_DFL);
  ::raise(sig);
}

long long now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now().time_since_epoch())
      .count();
}

std::string read_text(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void save(const fs::path& file, const std::string& text) {
  std::ofstream out(file, std::ios::binary);
  out << text;
}

/// The --set overrides of a saved input, beside it in <file>.set: one per line, with '\\' and
/// line feeds escaped (a backslash as two, a line feed as backslash-n), as --replay reads them.
void save_overrides(const fs::path& file, const std::vector<std::string>& sets) {
  if (sets.empty())
    return;
  std::ofstream out(file.string() + ".set", std::ios::binary);
  for (const std::string& s : sets) {
    for (const char c : s)
      out << (c == '\\' ? "\\\\" : c == '\n' ? "\\n" : std::string(1, c));
    out << '\n';
  }
}

std::vector<std::string> read_overrides(const fs::path& file) {
  std::vector<std::string> sets;
  std::ifstream in(file.string() + ".set", std::ios::binary);
  std::string line;
  while (std::getline(in, line)) {
    std::string s;
    for (std::size_t i = 0; i < line.size(); ++i) {
      if (line[i] == '\\' && i + 1 < line.size()) {
        s += line[i + 1] == 'n' ? '\n' : line[i + 1];
        ++i;
      } else {
        s += line[i];
      }
    }
    sets.push_back(s);
  }
  return sets;
}

// --- one input --------------------------------------------------------------------------------
enum class Outcome { Refused, Large, Built, Stepped };

/// The fuzzer builds scenes below this estimate, and sends only those (and refused inputs) to
/// `talus check`, which would build scenes up to 1 GB: a mutant that happens to be a valid case
/// of hundreds of megabytes is not a bug, and must not make the run slow or memory-hungry.
constexpr double kSmallScene = 64e6;

/// Valid mutants below this estimate are also stepped (kStepsPerMutant steps): the shipped cases
/// at their own resolution lie between 1 and 40 MB, so this steps the coarse ones and the
/// mutants whose grid or point spacing was coarsened, at a few milliseconds per step.
constexpr double kSteppedScene = 4e6;
constexpr int kStepsPerMutant = 3;

/// What a run of the fuzzer has seen, by outcome and by geometry.
struct Tally {
  std::size_t inputs = 0, refused = 0, parsed = 0, cli_runs = 0, failures = 0;
  std::size_t built[3] = {}, stepped[3] = {}; ///< plane strain, axisymmetric, 3D
  std::size_t numerical_failures = 0;         ///< stepped runs that ended in numerical failure
  std::size_t steps = 0;                      ///< steps the stepped runs took in all
};

int geometry_index(const talus::CaseSpec& spec) {
  if (spec.dimension == 3)
    return 2;
  return spec.geometry == talus::Geometry::Axisymmetric ? 1 : 0;
}

/// Steps a valid mutant for kStepsPerMutant steps in `scratch`. A run may end stopped (the
/// steps were taken), completed (a shorter run) or in numerical failure (a mutant may be valid
/// input and still an unstable model); anything else is a defect.
void step(const talus::CaseSpec& spec, const fs::path& scratch, Tally& tally) {
  talus::RunOptions options;
  options.out_dir = scratch;
  options.force = true;
  options.threads = 1;
  options.progress = false;
  int steps = 0;
  options.stop_after_step = [&steps](const talus::StepState&) -> std::optional<std::string> {
    if (++steps < kStepsPerMutant)
      return std::nullopt;
    return std::string("the fuzzer's steps were taken");
  };
  const talus::RunResult result = talus::run_case(spec, options);
  tally.steps += static_cast<std::size_t>(result.steps);
  if (result.status == "numerical_failure")
    ++tally.numerical_failures;
  else if (result.status != "stopped" && result.status != "completed")
    throw std::runtime_error("a stepped run ended with status \"" + result.status +
                             "\": " + result.message);
}

/// Reads `text` as the CLI would, builds the scene when the estimate is small and steps it when
/// it is smaller still. Throws what the reader, the builder or the run throws other than
/// InputError.
Outcome run_one(const std::string& text, const std::vector<std::string>& overrides,
                const fs::path& scratch, Tally& tally) {
  try {
    const talus::CaseSpec spec = talus::read_case_text(text, "fuzz.yaml", overrides);
    // The reader has refused what does not fit the machine; the fuzzer builds only small scenes
    // so that it tries many inputs.
    const double bytes = talus::estimate_memory(spec).total_bytes;
    if (bytes > kSmallScene)
      return Outcome::Large;
    if (spec.dimension == 3)
      talus::build_scene<3>(spec);
    else
      talus::build_scene<2>(spec); // plane strain and axisymmetry
    ++tally.built[geometry_index(spec)];
    if (bytes > kSteppedScene)
      return Outcome::Built;
    step(spec, scratch, tally);
    ++tally.stepped[geometry_index(spec)];
    return Outcome::Stepped;
  } catch (const talus::InputError&) {
    return Outcome::Refused;
  }
}

/// `talus check` on the input, through a file; the exit code, or -1 on a timeout.
int run_cli(const std::string& talus, const fs::path& file, const std::vector<std::string>& sets,
            int seconds) {
  std::vector<std::string> args{talus, "check", file.string()};
  for (const auto& s : sets) {
    args.push_back("--set");
    args.push_back(s);
  }
  std::vector<char*> argv;
  for (auto& a : args)
    argv.push_back(a.data());
  argv.push_back(nullptr);
  const pid_t pid = ::fork();
  if (pid == 0) {
    const int null = ::open("/dev/null", O_RDWR);
    ::dup2(null, 0);
    ::dup2(null, 1);
    ::dup2(null, 2);
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  const auto deadline = Clock::now() + std::chrono::seconds(seconds);
  int status = 0;
  while (true) {
    const pid_t r = ::waitpid(pid, &status, WNOHANG);
    if (r == pid)
      break;
    if (Clock::now() > deadline) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &status, 0);
      return -1;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  if (WIFEXITED(status))
    return WEXITSTATUS(status);
  return 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}

struct Options {
  double seconds = 30;
  std::uint64_t seed = 1;
  std::string talus;
  std::size_t cli_every = 50;
  double watchdog = 5;
  fs::path crash_dir = ".";
  std::vector<fs::path> corpus;
  std::string replay;
};

int usage() {
  std::fprintf(stderr, "usage: talus_fuzz_case_reader [--seconds N] [--seed S] [--talus PATH] "
                       "[--cli-every K] [--watchdog SECONDS] [--crash-dir DIR] [--corpus DIR]... "
                       "| --replay FILE\n");
  return 2;
}

} // namespace

int main(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has_value = i + 1 < argc;
    if (a == "--seconds" && has_value)
      o.seconds = std::atof(argv[++i]);
    else if (a == "--seed" && has_value)
      o.seed = std::strtoull(argv[++i], nullptr, 10);
    else if (a == "--talus" && has_value)
      o.talus = argv[++i];
    else if (a == "--cli-every" && has_value)
      o.cli_every = std::strtoull(argv[++i], nullptr, 10);
    else if (a == "--watchdog" && has_value)
      o.watchdog = std::atof(argv[++i]);
    else if (a == "--crash-dir" && has_value)
      o.crash_dir = argv[++i];
    else if (a == "--corpus" && has_value)
      o.corpus.emplace_back(argv[++i]);
    else if (a == "--replay" && has_value)
      o.replay = argv[++i];
    else
      return usage();
  }
  const fs::path scratch = fs::temp_directory_path() / ("talus-fuzz-" + std::to_string(::getpid()));
  if (!o.replay.empty()) {
    const std::string text = read_text(o.replay);
    Tally tally;
    try {
      const Outcome r = run_one(text, read_overrides(o.replay), scratch / "run", tally);
      std::error_code ec;
      fs::remove_all(scratch, ec);
      std::printf("fuzz: replay %s: %s\n", o.replay.c_str(),
                  r == Outcome::Refused ? "refused (InputError)" : "accepted");
      return 0;
    } catch (const std::exception& e) {
      std::printf("fuzz: replay %s: unexpected exception: %s\n", o.replay.c_str(), e.what());
      return 1;
    }
  }
  if (o.corpus.empty())
    o.corpus = {fs::path(TALUS_SOURCE_DIR) / "cases", fs::path(TALUS_SOURCE_DIR) / "verification"};
  std::vector<std::string> seeds;
  for (const fs::path& dir : o.corpus)
    for (const auto& entry : fs::directory_iterator(dir))
      if (entry.path().extension() == ".yaml")
        seeds.push_back(read_text(entry.path()));
  if (seeds.empty()) {
    std::fprintf(stderr, "fuzz: no .yaml seeds found\n");
    return 2;
  }
  fs::create_directories(o.crash_dir);
  const std::string crash_prefix =
      (o.crash_dir / ("fuzz-crash-" + std::to_string(o.seed) + "-")).string();

  for (int sig : {SIGSEGV, SIGABRT, SIGFPE, SIGBUS, SIGILL})
    ::signal(sig, on_crash);

  talus::fuzz::Mutator mutator(o.seed, seeds);
  std::atomic<bool> done{false};
  std::string hang_file;
  std::thread watchdog([&] {
    while (!done) {
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
      if (g_busy && static_cast<double>(now_ns() - g_started_ns) > o.watchdog * 1e9) {
        const std::string file = std::string(g_crash_path) + ".hang.yaml";
        if (g_input != nullptr)
          save(file, *g_input);
        save_overrides(file, g_sets);
        std::fprintf(stderr, "fuzz: HANG: an input took more than %g s; saved to %s\n", o.watchdog,
                     file.c_str());
        std::fflush(stderr);
        std::_Exit(1);
      }
    }
  });

  const auto start = Clock::now();
  Tally tally;
  std::size_t& inputs = tally.inputs;
  std::size_t& failures = tally.failures;
  double slowest = 0;
  fs::create_directories(scratch);
  const fs::path cli_file = scratch / "check.yaml";
  while (std::chrono::duration<double>(Clock::now() - start).count() < o.seconds) {
    const std::string text = mutator.mutant();
    const std::vector<std::string> sets = mutator.overrides();
    g_sets = sets;
    const std::string crash_path = crash_prefix + std::to_string(inputs) + ".yaml";
    std::snprintf(g_crash_path, sizeof g_crash_path, "%s", crash_path.c_str());
    g_input = &text;
    g_started_ns = now_ns();
    g_busy = true;
    const auto t0 = Clock::now();
    Outcome outcome = Outcome::Refused;
    try {
      outcome = run_one(text, sets, scratch / "run", tally);
      if (outcome == Outcome::Refused)
        ++tally.refused;
      else
        ++tally.parsed;
    } catch (const std::exception& e) {
      ++failures;
      save(crash_path, text);
      save_overrides(crash_path, sets);
      std::fprintf(stderr, "fuzz: FAILURE: exception other than InputError: %s; saved to %s\n",
                   e.what(), crash_path.c_str());
    } catch (...) {
      ++failures;
      save(crash_path, text);
      save_overrides(crash_path, sets);
      std::fprintf(stderr, "fuzz: FAILURE: unknown exception; saved to %s\n", crash_path.c_str());
    }
    g_busy = false;
    slowest = std::max(slowest, std::chrono::duration<double>(Clock::now() - t0).count());
    ++inputs;
    if (!o.talus.empty() && o.cli_every > 0 && inputs % o.cli_every == 0 &&
        outcome != Outcome::Large) {
      save(cli_file, text);
      const int code = run_cli(o.talus, cli_file, sets, static_cast<int>(o.watchdog) + 5);
      ++tally.cli_runs;
      if (code < 0 || code == talus::kExitOther || code > talus::kExitNumerical) {
        ++failures;
        const std::string file = crash_prefix + std::to_string(inputs) + ".cli.yaml";
        save(file, text);
        save_overrides(file, sets);
        std::fprintf(stderr, "fuzz: FAILURE: talus check exited %d%s; saved to %s\n", code,
                     code < 0 ? " (timeout)" : "", file.c_str());
      }
    }
    if (failures >= 10)
      break;
  }
  done = true;
  watchdog.join();
  std::error_code ec;
  fs::remove_all(scratch, ec);
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  const auto& b = tally.built;
  const auto& st = tally.stepped;
  std::printf(
      "fuzz: seed %llu, %.1f s, %zu inputs (%zu refused with InputError, %zu parsed); "
      "scenes built: %zu plane strain, %zu axisymmetric, %zu 3D; stepped %d steps: %zu "
      "plane strain, %zu axisymmetric, %zu 3D (%zu steps; %zu ended in numerical failure); %zu "
      "through talus check; slowest input %.3f s; %zu failures\n",
      static_cast<unsigned long long>(o.seed), seconds, inputs, tally.refused, tally.parsed, b[0],
      b[1], b[2], kStepsPerMutant, st[0], st[1], st[2], tally.steps, tally.numerical_failures,
      tally.cli_runs, slowest, failures);
  // A run that stepped no mutant of some geometry, or sent none through the binary, tested
  // nothing there: it fails rather than pass on an empty sample (30 s steps about 30 plane
  // strain, 6 axisymmetric and 6 3D mutants).
  bool covered = true;
  for (int g = 0; g < 3; ++g)
    if (st[g] == 0) {
      std::fprintf(stderr, "fuzz: FAILURE: no %s mutant was stepped\n",
                   g == 0   ? "plane strain"
                   : g == 1 ? "axisymmetric"
                            : "3D");
      covered = false;
    }
  if (!o.talus.empty() && o.cli_every > 0 && tally.cli_runs == 0) {
    std::fprintf(stderr, "fuzz: FAILURE: no input went through talus check\n");
    covered = false;
  }
  return failures == 0 && covered ? 0 : 1;
}
