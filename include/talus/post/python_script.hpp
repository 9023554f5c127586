#pragma once
// Runs one of the project's Python scripts (scripts/*.py) with Debian's /usr/bin/python3, whose
// matplotlib, numpy and h5py come from Debian packages (scripts/setup.sh), not any other
// python on PATH.
#include <filesystem>
#include <string>
#include <vector>

namespace talus {

/// scripts/ of the source tree, or of $TALUS_DATA_DIR when set (like verification_dir()).
std::filesystem::path scripts_dir();

/// Runs `/usr/bin/python3 scripts/<script> args...` and waits for it. Its stdout is passed
/// through; on a non-zero exit a std::runtime_error carries the script's error output.
void run_python_script(const std::string& script, const std::vector<std::string>& args);

} // namespace talus
