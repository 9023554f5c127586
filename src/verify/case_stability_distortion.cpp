// Extreme distortion: det F reaching zero must be caught and reported, never turned into NaN.
//  * Explicit: verification/stability_distortion.yaml throws a soft block inwards from every
//    side; in free flight det F = (1 - 20 t)^2 reaches 0 at t = 0.05 s (the material only delays
//    it). The run must end with exit 3, the message naming det F, the particle and the step, and
//    every frame on disk must be finite (the guard stops before a bad state is written).
//  * Implicit: verification/stability_compression.yaml with the top pushed down by 1.2 times
//    the block's height. No state without inverted points exists beyond 100 %, so the load
//    steps are cut back to min_dt and the run ends with exit 3, the last converged state as the
//    last frame (finite, det F > 0), and the Newton message.
#include "cases.hpp"

#include "talus/io/case_reader.hpp"

#include <cmath>
#include <fmt/format.h>

namespace talus::verify_cases {

namespace {

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

/// Whether every value of every particle field of every frame is finite and every det F > 0.
bool frames_are_finite(const ResultsReader& results) {
  for (Index f = 0; f < results.frame_count(); ++f) {
    for (const auto& field : results.frame_fields(f)) {
      Index rows = 0, cols = 0;
      for (double v : results.read(f, field, &rows, &cols))
        if (!std::isfinite(v))
          return false;
    }
    Index rows = 0, cols = 0;
    const auto F = results.read(f, "F", &rows, &cols);
    for (Index p = 0; p < rows; ++p) {
      const auto* a = &F[static_cast<std::size_t>(p * cols)];
      if (!(a[0] * a[4] - a[1] * a[3] > 0)) // row-major 3x3
        return false;
    }
  }
  return true;
}

} // namespace

VerificationCase stability_distortion() {
  VerificationCase vc;
  vc.name = "stability_distortion";
  vc.description = "det F -> 0: an explicit block collapsing onto its centre and an implicit "
                   "block compressed past its height stop with exit 3 naming det F (explicit: "
                   "particle and step), with only finite frames on disk.";
  vc.tiers = {"stability"};
  vc.run = [](const VerificationContext& ctx) {
    std::vector<Check> checks;
    const auto explicit_dir = ctx.out_dir / "explicit";
    const RunResult e =
        run_case(load_verification_case(ctx), RunOptions{explicit_dir, true, ctx.threads, false});
    checks.push_back(absolute_check("explicit: exit code", e.exit_code, kExitNumerical, 0.0,
                                    e.message.substr(0, 240)));
    checks.push_back(holds_check("explicit: message names det F, particle, step",
                                 contains(e.message, "det F") && contains(e.message, "particle") &&
                                     contains(e.message, "step")));
    const ResultsReader explicit_results(explicit_dir / "run.h5");
    checks.push_back(holds_check("explicit: every frame finite, det F > 0",
                                 frames_are_finite(explicit_results)));
    checks.push_back(within_check("explicit: time of the stop", e.final_time, 0.05, 0.2,
                                  "free flight collapses at 0.05 s, the material only delays it; "
                                  "measured 0.07 s"));

    auto implicit_spec =
        read_case_file((verification_dir() / "stability_compression.yaml").string(),
                       {"prescribed[0].displacement=[~, -1.2]", "time.dt=0.1"});
    const auto implicit_dir = ctx.out_dir / "implicit";
    const RunResult i = run_case(implicit_spec, RunOptions{implicit_dir, true, ctx.threads, false});
    checks.push_back(absolute_check("implicit: exit code", i.exit_code, kExitNumerical, 0.0,
                                    i.message.substr(0, 240)));
    const ResultsReader implicit_results(implicit_dir / "run.h5");
    checks.push_back(holds_check("implicit: every frame finite, det F > 0",
                                 frames_are_finite(implicit_results)));
    const double last = implicit_results.frame_time(implicit_results.frame_count() - 1);
    checks.push_back(within_check("implicit: last converged compression / height", 1.2 * last, 0.9,
                                  1.0,
                                  "the load factor of the last frame times 1.2: close to, never "
                                  "past, a flat block (measured 0.96)"));
    checks.push_back(report_only("implicit: cut-backs", i.extra.at("cutbacks")));
    return checks;
  };
  return vc;
}

} // namespace talus::verify_cases
