#pragma once
// The verification suite: each case runs real scenes through run_case and compares measured
// quantities with analytical references under a tolerance justified in the case's source.
#include "talus/io/case_spec.hpp"

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace talus {

struct Check {
  std::string quantity;
  double measured = 0;
  double reference = 0;
  double error = 0;     ///< as defined by the case (relative unless the quantity says otherwise)
  double tolerance = 0; ///< passed when error <= tolerance
  bool passed = false;
  std::string note;      ///< what the error measures, or extra facts (observed order, ...)
  bool at_least = false; ///< passed when measured >= tolerance instead (e.g. convergence order)
};

/// Helpers that build a Check and decide pass/fail.
Check relative_check(std::string quantity, double measured, double reference, double tolerance,
                     std::string note = {});
Check bound_check(std::string quantity, double measured, double bound, std::string note = {});
/// Passes when measured >= minimum (observed convergence orders).
Check minimum_check(std::string quantity, double measured, double minimum, std::string note = {});
/// Report-only figure (always passes); for numbers the issue says to report, not to bound.
Check report_only(std::string quantity, double measured, std::string note = {});

struct VerificationContext {
  std::filesystem::path case_file; ///< verification/<name>.yaml
  std::filesystem::path out_dir;   ///< where this case may write its runs and plots
  std::string tier;                ///< "fast", "full" or "stability"
  int threads = 0;
};

struct VerificationCase {
  std::string name;
  std::string description;
  std::vector<std::string> tiers; ///< tiers that include the case
  std::string scene;              ///< verification/<scene>.yaml; empty: the case's name
  std::function<std::vector<Check>(const VerificationContext&)> run;
};

/// Every registered case, in report order.
const std::vector<VerificationCase>& verification_cases();

/// Directory holding verification/*.yaml (TALUS_DATA_DIR env var, else the source tree).
std::filesystem::path verification_dir();

/// Reads verification/<name>.yaml with overrides applied.
CaseSpec load_verification_case(const VerificationContext& ctx,
                                const std::vector<std::string>& overrides = {});

struct VerifyOptions {
  std::string tier = "fast";
  std::filesystem::path out_dir = "results/verify";
  std::vector<std::string> only; ///< run just these cases (empty: all of the tier)
  int threads = 0;
  bool force = false;
};

/// Runs the tier, prints the table, writes report.md and report.json; returns the exit code
/// (0 all passed, 3 a check failed, 1 a case crashed).
int run_verification(const VerifyOptions& options);

} // namespace talus
