#include "talus/verify/verification.hpp"

#include "cases.hpp"
#include "talus/core/errors.hpp"
#include "talus/io/case_reader.hpp"

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fmt/format.h>
#include <fstream>
#include <nlohmann/json.hpp>

namespace talus {

namespace fs = std::filesystem;

Check relative_check(std::string quantity, double measured, double reference, double tolerance,
                     std::string note) {
  Check c{std::move(quantity), measured, reference, 0.0, tolerance, false, std::move(note)};
  c.error = std::abs(measured - reference) / std::abs(reference);
  c.passed = c.error <= tolerance;
  return c;
}

Check bound_check(std::string quantity, double measured, double bound, std::string note) {
  Check c{std::move(quantity), measured, 0.0, measured, bound, false, std::move(note)};
  c.passed = std::isfinite(measured) && measured <= bound;
  return c;
}

Check minimum_check(std::string quantity, double measured, double minimum, std::string note) {
  Check c{std::move(quantity), measured, NAN, measured, minimum, false, std::move(note), true};
  c.passed = std::isfinite(measured) && measured >= minimum;
  return c;
}

Check report_only(std::string quantity, double measured, std::string note) {
  return Check{std::move(quantity), measured, NAN, NAN, NAN, true, std::move(note)};
}

const std::vector<VerificationCase>& verification_cases() {
  static const std::vector<VerificationCase> cases = {verify_cases::vibrating_bar(),
                                                      verify_cases::vibrating_bar_implicit(),
                                                      verify_cases::colliding_discs(),
                                                      verify_cases::rigid_translation(),
                                                      verify_cases::rigid_rotation(),
                                                      verify_cases::cantilever(),
                                                      verify_cases::self_weight_column(),
                                                      verify_cases::grashof(),
                                                      verify_cases::strip_footing(),
                                                      verify_cases::slope_fos(),
                                                      verify_cases::single_element(),
                                                      verify_cases::stability_explicit_cfl(),
                                                      verify_cases::stability_implicit_dt(),
                                                      verify_cases::stability_cell_crossing(),
                                                      verify_cases::stability_tiny_mass(),
                                                      verify_cases::stability_stiffness_contrast(),
                                                      verify_cases::stability_incompressibility(),
                                                      verify_cases::stability_rotation(),
                                                      verify_cases::stability_distortion(),
                                                      verify_cases::stability_perturbed(),
                                                      verify_cases::stability_recovery()};
  return cases;
}

fs::path verification_dir() {
  if (const char* dir = std::getenv("TALUS_DATA_DIR"))
    return fs::path(dir) / "verification";
  return fs::path(TALUS_SOURCE_DIR) / "verification";
}

CaseSpec load_verification_case(const VerificationContext& ctx,
                                const std::vector<std::string>& overrides) {
  return read_case_file(ctx.case_file.string(), overrides);
}

namespace {

struct CaseOutcome {
  const VerificationCase* vcase;
  std::vector<Check> checks;
  double wall_seconds;
};

std::string tolerance_text(const Check& c) {
  if (std::isnan(c.tolerance))
    return "-";
  return (c.at_least ? ">= " : "") + fmt::format("{:.4g}", c.tolerance);
}

std::string number(double v) {
  if (std::isnan(v))
    return "-";
  return fmt::format("{:.4g}", v);
}

void print_table(const std::vector<CaseOutcome>& outcomes) {
  fmt::print("{:<20} {:<44} {:>11} {:>11} {:>10} {:>10}  {}\n", "case", "quantity", "measured",
             "reference", "error", "tolerance", "result");
  fmt::print("{}\n", std::string(118, '-'));
  for (const auto& o : outcomes)
    for (const auto& c : o.checks)
      fmt::print("{:<20} {:<44} {:>11} {:>11} {:>10} {:>10}  {}\n", o.vcase->name, c.quantity,
                 number(c.measured), number(c.reference), number(c.error), tolerance_text(c),
                 std::isnan(c.tolerance) ? "report" : (c.passed ? "PASS" : "FAIL"));
}

void write_reports(const fs::path& dir, const std::string& tier,
                   const std::vector<CaseOutcome>& outcomes, bool all_passed) {
  nlohmann::json list = nlohmann::json::array();
  std::ofstream md(dir / "report.md");
  md << "# Talus verification report (tier " << tier << ")\n\n"
     << "Overall: " << (all_passed ? "**PASS**" : "**FAIL**") << "\n\n";
  for (const auto& o : outcomes) {
    md << "## " << o.vcase->name << "\n\n"
       << o.vcase->description << "\n\n"
       << fmt::format("Wall time: {:.2f} s\n\n", o.wall_seconds)
       << "| quantity | measured | reference | error | tolerance | result | note |\n"
       << "|---|---|---|---|---|---|---|\n";
    for (const auto& c : o.checks) {
      md << fmt::format("| {} | {} | {} | {} | {} | {} | {} |\n", c.quantity, number(c.measured),
                        number(c.reference), number(c.error), tolerance_text(c),
                        std::isnan(c.tolerance) ? "report" : (c.passed ? "PASS" : "FAIL"), c.note);
      auto finite_or_null = [](double v) -> nlohmann::json {
        return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
      };
      list.push_back({{"case", o.vcase->name},
                      {"quantity", c.quantity},
                      {"measured", finite_or_null(c.measured)},
                      {"reference", finite_or_null(c.reference)},
                      {"error", finite_or_null(c.error)},
                      {"tolerance", finite_or_null(c.tolerance)},
                      {"passed", c.passed},
                      {"tolerance_is_minimum", c.at_least},
                      {"note", c.note},
                      {"wall_seconds", o.wall_seconds}});
    }
    md << "\n";
    for (const auto& png : {o.vcase->name + ".png"})
      if (fs::exists(dir / o.vcase->name / png))
        md << "![" << o.vcase->name << "](" << o.vcase->name << "/" << png << ")\n\n";
  }
  std::ofstream(dir / "report.json") << list.dump(2) << "\n";
}

} // namespace

int run_verification(const VerifyOptions& options) {
  const fs::path out = options.out_dir;
  fs::create_directories(out);
  std::vector<CaseOutcome> outcomes;
  bool all_passed = true;
  bool crashed = false;
  for (const auto& vc : verification_cases()) {
    const bool in_tier =
        std::find(vc.tiers.begin(), vc.tiers.end(), options.tier) != vc.tiers.end();
    const bool selected = options.only.empty() ? in_tier
                                               : std::find(options.only.begin(), options.only.end(),
                                                           vc.name) != options.only.end();
    if (!selected)
      continue;
    VerificationContext ctx;
    ctx.case_file = verification_dir() / ((vc.scene.empty() ? vc.name : vc.scene) + ".yaml");
    ctx.out_dir = out / vc.name;
    ctx.tier = options.tier;
    ctx.threads = options.threads;
    // The verification directory is the suite's own scratch space: each case starts clean.
    fs::remove_all(ctx.out_dir);
    fs::create_directories(ctx.out_dir);
    fmt::print(stderr, "verify: {} ...\n", vc.name);
    const auto t0 = std::chrono::steady_clock::now();
    CaseOutcome outcome{&vc, {}, 0.0};
    try {
      outcome.checks = vc.run(ctx);
    } catch (const std::exception& e) {
      outcome.checks.push_back(Check{"case ran to completion", NAN, NAN, NAN, 0.0, false,
                                     std::string("error: ") + e.what()});
      crashed = true;
    }
    outcome.wall_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    for (const auto& c : outcome.checks)
      all_passed = all_passed && c.passed;
    outcomes.push_back(std::move(outcome));
  }
  if (outcomes.empty())
    throw InputError({"--case", 0, 0, ""}, "no verification case matches the selection");
  print_table(outcomes);
  write_reports(out, options.tier, outcomes, all_passed);
  fmt::print("\n{} — report: {}\n", all_passed ? "ALL PASSED" : "SOME CHECKS FAILED",
             (out / "report.md").string());
  if (crashed)
    return kExitOther;
  return all_passed ? kExitOk : kExitNumerical;
}

} // namespace talus
