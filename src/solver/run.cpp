#include "talus/solver/run.hpp"

#include "case_run.hpp"
#include "talus/core/errors.hpp"

#include <fmt/format.h>
#include <functional>
#include <optional>

namespace talus {

namespace fs = std::filesystem;

namespace {

// Result files a run owns; --force replaces exactly these and leaves anything else alone.
const char* const kResultFiles[] = {"run.h5",       "run.xmf",    "timeseries.csv",
                                    "summary.json", "newton.log", "checkpoints"};

} // namespace

void claim_output_directory(const fs::path& dir, bool force,
                            std::span<const char* const> owned_entries) {
  std::error_code ec;
  if (!fs::exists(dir, ec))
    return;
  if (!fs::is_directory(dir, ec))
    throw InputError({"--out", 0, 0, ""},
                     fmt::format("'{}' exists and is not a directory", dir.string()));
  if (fs::is_empty(dir, ec))
    return;
  if (!force)
    throw InputError({"--out", 0, 0, ""},
                     fmt::format("output directory '{}' already holds results; choose another "
                                 "--out or pass --force to replace them",
                                 dir.string()));
  for (const char* name : owned_entries)
    fs::remove_all(dir / name, ec);
}

void prepare_output_directory(const fs::path& dir, bool force) {
  claim_output_directory(dir, force, kResultFiles);
}

void on_root(const Communicator& ranks, const std::function<void()>& work) {
  std::optional<std::string> failure;
  if (ranks.root()) {
    try {
      work();
    } catch (const InputError& e) {
      failure = e.what();
      ranks.first_message(failure);
      throw;
    }
  }
  if (const auto first = ranks.first_message(failure))
    throw InputError({"mpirun", 0, 0, ""}, *first);
}

RunResult run_case(const CaseSpec& spec, const RunOptions& options) {
  return spec.dimension == 3 ? run_detail::Run<3>(spec, options).execute()
                             : run_detail::Run<2>(spec, options).execute();
}

} // namespace talus
