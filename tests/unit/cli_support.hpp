#pragma once
// Helpers of the end-to-end tests of the `talus` executable (test_cli*.cpp): a child process
// running the real binary (TALUS_BINARY) with its output captured, the `Cli` fixture that runs it
// in a fresh temporary directory, and snapshots of result files to show that nothing was touched.
#include "temporary_directory.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/time.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace talus::test_support {

namespace fs = std::filesystem;

inline const char* const kResultFiles[] = {"run.h5", "run.xmf", "timeseries.csv", "summary.json"};

inline std::string read_file(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

inline void write_file(const fs::path& file, const std::string& text) {
  std::ofstream out(file, std::ios::binary);
  out << text;
  ASSERT_TRUE(out.good()) << "cannot write " << file;
}

/// `text` with the one occurrence of `from` replaced by `to` (a test failure if `from` does not
/// occur exactly once).
inline std::string replaced_once(const std::string& from, const std::string& to, std::string text) {
  const auto at = text.find(from);
  if (at == std::string::npos || text.find(from, at + 1) != std::string::npos) {
    ADD_FAILURE() << "test bug: '" << from << "' must occur exactly once in the case text";
    return text;
  }
  return text.replace(at, from.size(), to);
}

inline nlohmann::json read_json(const fs::path& file) {
  return nlohmann::json::parse(read_file(file));
}

inline std::set<std::string> directory_listing(const fs::path& dir) {
  std::set<std::string> names;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec))
    names.insert(entry.path().filename().string());
  return names;
}

/// What a finished `talus` process left: its exit code (128 + signal if it was killed) and its
/// captured output.
struct Outcome {
  int exit_code = -1;
  double cpu_seconds = 0; ///< user + system time of the process (and its re-execution)
  std::string out;
  std::string err;
  std::string describe() const {
    return "exit code " + std::to_string(exit_code) + "\n--- stdout ---\n" + out +
           "--- stderr ---\n" + err;
  }
};

inline int decode_status(int status) {
  if (WIFEXITED(status))
    return WEXITSTATUS(status);
  if (WIFSIGNALED(status))
    return 128 + WTERMSIG(status);
  return -1;
}

/// A `talus` child process (or `program`, e.g. mpirun) with stdout and stderr redirected to
/// files.
class Child {
public:
  Child(const std::vector<std::string>& args, const fs::path& cwd, const fs::path& capture_dir,
        const std::string& program = TALUS_BINARY)
      : out_file_(capture_dir / "stdout.txt"), err_file_(capture_dir / "stderr.txt") {
    // Everything the child needs is prepared before fork(): after it, only async-signal-safe
    // calls.
    std::vector<std::string> argv_text{program};
    argv_text.insert(argv_text.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (auto& a : argv_text)
      argv.push_back(a.data());
    argv.push_back(nullptr);
    const std::string cwd_text = cwd.string();
    const std::string out_text = out_file_.string();
    const std::string err_text = err_file_.string();

    pid_ = ::fork();
    if (pid_ == 0) {
      if (::chdir(cwd_text.c_str()) != 0)
        ::_exit(126);
      const int out = ::open(out_text.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      const int err = ::open(err_text.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      const int null = ::open("/dev/null", O_RDONLY);
      if (out < 0 || err < 0 || null < 0 || ::dup2(out, 1) < 0 || ::dup2(err, 2) < 0 ||
          ::dup2(null, 0) < 0)
        ::_exit(126);
      ::signal(SIGINT, SIG_DFL);
      ::signal(SIGTERM, SIG_DFL);
      sigset_t none;
      sigemptyset(&none);
      ::sigprocmask(SIG_SETMASK, &none, nullptr);
      ::execv(argv[0], argv.data());
      ::_exit(127);
    }
  }
  ~Child() {
    if (pid_ > 0 && !reaped_) {
      ::kill(pid_, SIGKILL);
      int status = 0;
      ::waitpid(pid_, &status, 0);
    }
  }
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;

  bool started() const { return pid_ > 0; }
  pid_t pid() const { return pid_; }

  /// Non-blocking: the outcome if the child has exited, otherwise nothing.
  std::optional<Outcome> poll() {
    if (reaped_)
      return outcome_;
    int status = 0;
    const pid_t r = ::wait4(pid_, &status, WNOHANG, &usage_);
    if (r != pid_)
      return std::nullopt;
    finish(status);
    return outcome_;
  }

  /// Blocks until the child exits.
  Outcome wait() {
    if (!reaped_) {
      int status = 0;
      pid_t r;
      do
        r = ::wait4(pid_, &status, 0, &usage_);
      while (r < 0 && errno == EINTR);
      finish(r == pid_ ? status : -1);
    }
    return outcome_;
  }

  /// Waits at most `cap` for the child to exit; kills it (SIGKILL) when the cap is reached.
  std::optional<Outcome> wait_at_most(std::chrono::seconds cap) {
    const auto deadline = std::chrono::steady_clock::now() + cap;
    while (std::chrono::steady_clock::now() < deadline) {
      if (auto o = poll())
        return o;
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    if (auto o = poll())
      return o;
    ::kill(pid_, SIGKILL);
    wait();
    return std::nullopt;
  }

  /// Output captured so far.
  std::string output_so_far() const {
    return "--- stdout ---\n" + read_file(out_file_) + "--- stderr ---\n" + read_file(err_file_);
  }

private:
  void finish(int status) {
    reaped_ = true;
    outcome_.exit_code = status == -1 ? -1 : decode_status(status);
    outcome_.out = read_file(out_file_);
    outcome_.err = read_file(err_file_);
    const auto seconds = [](const timeval& t) {
      return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec);
    };
    outcome_.cpu_seconds = seconds(usage_.ru_utime) + seconds(usage_.ru_stime);
  }

  pid_t pid_ = -1;
  struct rusage usage_ {};
  bool reaped_ = false;
  Outcome outcome_;
  fs::path out_file_, err_file_;
};

/// Per-test fixture: a fresh temporary directory `root` holding `work` (the child's working
/// directory, where the case files and output directories go) and the captured output files.
class Cli : public talus::test_support::TemporaryDirectoryTest {
protected:
  void SetUp() override {
    ASSERT_TRUE(fs::is_regular_file(TALUS_BINARY)) << "talus binary not found: " << TALUS_BINARY;
    TemporaryDirectoryTest::SetUp();
    if (HasFatalFailure())
      return;
    work_ = root_ / "work";
    fs::create_directory(work_);
  }

  const fs::path& work() const { return work_; }

  /// Runs `talus args...` in `cwd` (default: the work directory) and waits for it.
  Outcome talus(const std::vector<std::string>& args, const fs::path& cwd = {}) {
    Child child(args, cwd.empty() ? work_ : cwd, root_);
    if (!child.started()) {
      ADD_FAILURE() << "fork failed";
      return {};
    }
    return child.wait();
  }

  fs::path work_;
};

/// The four result files of a run, byte for byte, with their modification times.
struct Snapshot {
  std::map<std::string, std::string> content;
  std::map<std::string, fs::file_time_type> mtime;
  std::uintmax_t h5_size = 0;
};

inline Snapshot snapshot(const fs::path& dir) {
  Snapshot s;
  for (const char* name : kResultFiles) {
    s.content[name] = read_file(dir / name);
    std::error_code ec;
    s.mtime[name] = fs::last_write_time(dir / name, ec);
  }
  std::error_code ec;
  s.h5_size = fs::file_size(dir / "run.h5", ec);
  return s;
}

inline void expect_unchanged(const Snapshot& before, const fs::path& dir) {
  const Snapshot now = snapshot(dir);
  for (const char* name : kResultFiles) {
    EXPECT_TRUE(fs::is_regular_file(dir / name)) << name << " was removed";
    EXPECT_TRUE(now.content.at(name) == before.content.at(name)) << name << " was changed";
    EXPECT_TRUE(now.mtime.at(name) == before.mtime.at(name)) << name << " was rewritten";
  }
  EXPECT_EQ(now.h5_size, before.h5_size);
}

} // namespace talus::test_support
