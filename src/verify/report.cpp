#include "report.hpp"

#include <cmath>
#include <fmt/format.h>
#include <fstream>
#include <nlohmann/json.hpp>

namespace talus::verify_report {

namespace fs = std::filesystem;

namespace {

std::string number(double v) {
  if (std::isnan(v))
    return "-";
  return fmt::format("{:.4g}", v);
}

std::string measured_text(const Check& c) {
  if (c.acceptance == Acceptance::holds)
    return c.passed ? "yes" : "no";
  return number(c.measured);
}

std::string acceptance_name(Acceptance a) {
  switch (a) {
  case Acceptance::relative:
    return "relative";
  case Acceptance::absolute:
    return "absolute";
  case Acceptance::at_most:
    return "at_most";
  case Acceptance::at_least:
    return "at_least";
  case Acceptance::within:
    return "within";
  case Acceptance::holds:
    return "holds";
  case Acceptance::report:
    return "report";
  }
  return "report";
}

std::string note_text(const Check& c) {
  if (c.known_defect.empty())
    return c.note;
  return "known defect: " + c.known_defect + (c.note.empty() ? "" : "; " + c.note);
}

nlohmann::json finite_or_null(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

constexpr const char* kColumnLegend =
    "Columns: **measured** the quantity; **reference** the analytical or independent value it is "
    "compared with; **error** |measured - reference| / |reference| (`rel`) or |measured - "
    "reference| (`abs`); **accepted** the range the error (`rel`, `abs`) or else the measured "
    "value must lie in. **KNOWN FAIL**: the check exposes a known defect, named in the note, "
    "and still fails its bound; **UNEXPECTED PASS**: a known failure that now passes (the suite "
    "fails until its mark is removed); **report**: a figure for the record that decides "
    "nothing.";

} // namespace

Tally tally(const std::vector<CaseOutcome>& outcomes) {
  Tally t;
  for (const auto& o : outcomes)
    for (const auto& c : o.checks)
      switch (c.verdict()) {
      case Verdict::pass:
        ++t.passed;
        break;
      case Verdict::fail:
        ++t.failed;
        break;
      case Verdict::known_failure:
        ++t.known_failures;
        break;
      case Verdict::unexpected_pass:
        ++t.unexpected_passes;
        break;
      case Verdict::report:
        ++t.reports;
        break;
      }
  return t;
}

std::string verdict_text(Verdict v) {
  switch (v) {
  case Verdict::pass:
    return "PASS";
  case Verdict::fail:
    return "FAIL";
  case Verdict::known_failure:
    return "KNOWN FAIL";
  case Verdict::unexpected_pass:
    return "UNEXPECTED PASS";
  case Verdict::report:
    return "report";
  }
  return "report";
}

std::string acceptance_text(const Check& c) {
  switch (c.acceptance) {
  case Acceptance::relative:
    return "rel <= " + number(c.upper);
  case Acceptance::absolute:
    return "abs <= " + number(c.upper);
  case Acceptance::at_most:
    return "<= " + number(c.upper);
  case Acceptance::at_least:
    return ">= " + number(c.lower);
  case Acceptance::within:
    return fmt::format("[{}, {}]", number(c.lower), number(c.upper));
  case Acceptance::holds:
    return "must hold";
  case Acceptance::report:
    return "-";
  }
  return "-";
}

void print_table(const std::vector<CaseOutcome>& outcomes) {
  fmt::print("{:<20} {:<48} {:>11} {:>11} {:>10} {:>18}  {}\n", "case", "quantity", "measured",
             "reference", "error", "accepted", "result");
  fmt::print("{}\n", std::string(132, '-'));
  for (const auto& o : outcomes)
    for (const auto& c : o.checks)
      fmt::print("{:<20} {:<48} {:>11} {:>11} {:>10} {:>18}  {}\n", o.vcase->name, c.quantity,
                 measured_text(c), number(c.reference), number(c.error), acceptance_text(c),
                 verdict_text(c.verdict()));
}

std::string summary_line(const Tally& t) {
  std::string line = fmt::format("{} passed, {} failed", t.passed, t.failed);
  if (t.known_failures > 0)
    line += fmt::format(", {} known failure{}", t.known_failures, t.known_failures > 1 ? "s" : "");
  if (t.unexpected_passes > 0)
    line += fmt::format(", {} unexpected pass{} (remove the known-failure mark)",
                        t.unexpected_passes, t.unexpected_passes > 1 ? "es" : "");
  return line + fmt::format(", {} reported", t.reports);
}

void write_reports(const fs::path& dir, const std::string& tier,
                   const std::vector<CaseOutcome>& outcomes) {
  const Tally t = tally(outcomes);
  nlohmann::json list = nlohmann::json::array();
  std::ofstream md(dir / "report.md");
  md << "# Talus verification report (tier " << tier << ")\n\n"
     << "Overall: " << (t.all_held() ? "**PASS**" : "**FAIL**") << " (" << summary_line(t)
     << ")\n\n"
     << kColumnLegend << "\n\n"
     << "What each case asserts, and why its bounds are what they are: "
     << (verification_dir().parent_path() / "docs" / "verification.md").string() << "\n\n";
  if (t.known_failures + t.unexpected_passes > 0) {
    md << "Known defects:\n\n";
    for (const auto& o : outcomes)
      for (const auto& c : o.checks)
        if (!c.known_defect.empty())
          md << "* " << o.vcase->name << ", " << c.quantity << " (" << verdict_text(c.verdict())
             << "): " << c.known_defect << "\n";
    md << "\n";
  }
  for (const auto& o : outcomes) {
    md << "## " << o.vcase->name << "\n\n"
       << o.vcase->description << "\n\n"
       << fmt::format("Wall time: {:.2f} s\n\n", o.wall_seconds)
       << "| quantity | measured | reference | error | accepted | result | note |\n"
       << "|---|---|---|---|---|---|---|\n";
    for (const auto& c : o.checks) {
      md << fmt::format("| {} | {} | {} | {} | {} | {} | {} |\n", c.quantity, measured_text(c),
                        number(c.reference), number(c.error), acceptance_text(c),
                        verdict_text(c.verdict()), note_text(c));
      list.push_back({{"case", o.vcase->name},
                      {"quantity", c.quantity},
                      {"acceptance", acceptance_name(c.acceptance)},
                      {"measured", finite_or_null(c.measured)},
                      {"reference", finite_or_null(c.reference)},
                      {"error", finite_or_null(c.error)},
                      {"lower", finite_or_null(c.lower)},
                      {"upper", finite_or_null(c.upper)},
                      {"result", verdict_text(c.verdict())},
                      {"passed", c.passed},
                      {"known_defect", c.known_defect},
                      {"note", c.note},
                      {"wall_seconds", o.wall_seconds}});
    }
    md << "\n";
    const fs::path png = dir / o.vcase->name / (o.vcase->name + ".png");
    if (fs::exists(png))
      md << "![" << o.vcase->name << "](" << o.vcase->name << "/" << o.vcase->name << ".png)\n\n";
  }
  std::ofstream(dir / "report.json") << list.dump(2) << "\n";
}

} // namespace talus::verify_report
