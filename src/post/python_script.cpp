// Runs scripts/*.py through /usr/bin/python3 (include/talus/post/python_script.hpp): argv is
// passed as is (no shell, so paths need no quoting) and stderr is captured in a temporary file
// for the error message.
#include "talus/post/python_script.hpp"

#include <cstdlib>
#include <fcntl.h>
#include <fmt/format.h>
#include <fstream>
#include <spawn.h>
#include <sstream>
#include <stdexcept>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

namespace talus {

namespace fs = std::filesystem;

fs::path scripts_dir() {
  if (const char* dir = std::getenv("TALUS_DATA_DIR"))
    return fs::path(dir) / "scripts";
  return fs::path(TALUS_SOURCE_DIR) / "scripts";
}

void run_python_script(const std::string& script, const std::vector<std::string>& args) {
  const fs::path path = scripts_dir() / script;
  if (!fs::exists(path))
    throw std::runtime_error("script not found: " + path.string());
  std::vector<std::string> argv_text{"/usr/bin/python3", path.string()};
  argv_text.insert(argv_text.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : argv_text)
    argv.push_back(a.data());
  argv.push_back(nullptr);

  char log_name[] = "/tmp/talus-python-XXXXXX";
  const int log_fd = ::mkstemp(log_name);
  if (log_fd < 0)
    throw std::runtime_error("cannot create a temporary file for the script's error output");
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, log_fd, 2);
  pid_t pid = 0;
  const int spawned = ::posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(log_fd);
  int status = 0;
  if (spawned == 0)
    ::waitpid(pid, &status, 0);
  std::stringstream errors;
  errors << std::ifstream(log_name).rdbuf();
  ::unlink(log_name);
  if (spawned != 0)
    throw std::runtime_error(fmt::format("cannot start /usr/bin/python3 for {}", path.string()));
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw std::runtime_error(fmt::format("{} failed (exit status {}):\n{}", path.string(),
                                         WIFEXITED(status) ? WEXITSTATUS(status) : -1,
                                         errors.str()));
}

} // namespace talus
