#pragma once
// The verification suite: each case runs real scenes through run_case and compares measured
// quantities with analytical references under a tolerance justified in the case's source.
#include "talus/spec/case_spec.hpp"

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace talus {

/// How a check decides. Every kind but `report` can fail; two-sided kinds (`relative`,
/// `absolute`, `within`) are for quantities that can be wrong both ways.
enum class Acceptance {
  relative, ///< |measured - reference| / |reference| <= tolerance
  absolute, ///< |measured - reference| <= tolerance
  at_most,  ///< measured <= upper
  at_least, ///< measured >= lower
  within,   ///< lower <= measured <= upper
  holds,    ///< a yes/no fact that must be yes (measured 1 or 0)
  report,   ///< a figure for the record that decides nothing
};

/// What the report prints in its result column.
enum class Verdict { pass, fail, known_failure, unexpected_pass, report };

struct Check {
  std::string quantity;
  Acceptance acceptance = Acceptance::report;
  double measured = 0;
  double reference = 0; ///< relative / absolute only (NaN otherwise)
  double error = 0;     ///< relative / absolute only: the deviation from the reference
  double lower = 0;     ///< accepted range: of `error` (relative, absolute) or of `measured`
  double upper = 0;
  bool passed = false; ///< the acceptance holds (always true for a report)
  std::string note;    ///< what the quantity measures, why this bound
  /// Non-empty: a known defect that this check exposes and that is not fixed yet. The check
  /// keeps its bound; the report shows KNOWN FAIL, and UNEXPECTED PASS (a failure of the suite,
  /// so that the mark is removed) once the defect is gone.
  std::string known_defect;

  Verdict verdict() const;
};

// Builders: each computes `passed` from its acceptance.
Check relative_check(std::string quantity, double measured, double reference, double tolerance,
                     std::string note = {});
Check absolute_check(std::string quantity, double measured, double reference, double tolerance,
                     std::string note = {});
Check at_most_check(std::string quantity, double measured, double upper, std::string note = {});
Check at_least_check(std::string quantity, double measured, double lower, std::string note = {});
Check within_check(std::string quantity, double measured, double lower, double upper,
                   std::string note = {});
Check holds_check(std::string quantity, bool holds, std::string note = {});
/// Report-only figure: context for the reader (a resolution, a count, a wall time).
Check report_only(std::string quantity, double measured, std::string note = {});
/// Marks `check` as exposing a known, not yet fixed defect (see Check::known_defect).
Check known_failure(Check check, std::string defect);

/// log2(coarse / fine) for a refinement by 2: the observed convergence order.
double observed_order(double coarse_error, double fine_error);

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
  /// `talus verify --mpi N` runs it under mpirun with the same checks: the explicit cases and
  /// the implicit ones whose checks hold there (the iterative solve Belos does in a distributed
  /// run, where the serial run factorises).
  bool distributable = false;
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
  /// > 0: run the selected cases that distribute under `mpirun -np mpi` (the others are not
  /// run; selecting one by --case is refused).
  int mpi = 0;
  /// Print the selected cases' names, one per line, and run none.
  bool list = false;
};

/// Runs the tier, prints the table, writes report.md and report.json; returns the exit code
/// (0 every check passed or failed as a known failure, 3 a check failed or a known failure
/// passed, 1 a case crashed).
int run_verification(const VerifyOptions& options);

} // namespace talus
