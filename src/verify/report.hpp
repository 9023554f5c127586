#pragma once
// The verification report: the console table, report.md and report.json.
#include "talus/verify/verification.hpp"

#include <filesystem>
#include <string>
#include <vector>

namespace talus::verify_report {

struct CaseOutcome {
  const VerificationCase* vcase;
  std::vector<Check> checks;
  double wall_seconds;
};

/// Counts of the verdicts over every check of the outcomes.
struct Tally {
  int passed = 0, failed = 0, known_failures = 0, unexpected_passes = 0, reports = 0;
  bool all_held() const { return failed == 0 && unexpected_passes == 0; }
};
Tally tally(const std::vector<CaseOutcome>& outcomes);

/// The result column: PASS, FAIL, KNOWN FAIL, UNEXPECTED PASS or report.
std::string verdict_text(Verdict v);
/// The acceptance column: "rel <= 0.01", "<= 0.05", "[1.5, 2.5]", "must hold", ...
std::string acceptance_text(const Check& c);

void print_table(const std::vector<CaseOutcome>& outcomes);
void write_reports(const std::filesystem::path& dir, const std::string& tier,
                   const std::vector<CaseOutcome>& outcomes);
/// One line: how many checks passed, failed, failed as known, passed unexpectedly.
std::string summary_line(const Tally& t);

} // namespace talus::verify_report
