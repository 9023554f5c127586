// The implicit solver's recovery path (Newton, then line search, then halving the load step
// down to min_dt; docs/architecture.md "Newton strategy").
//  * Load far past the limit: verification/stability_plastic_tension.yaml ramps a traction to
//    twice the plane-strain limit of a perfectly plastic von Mises block: equilibrium exists
//    up to the load factor 1/sqrt(3) and never after. The run must end with exit 3 and a
//    message naming the minimum load step, after cutting back, with the last converged state as
//    the last frame. Its load factor must lie within 0.5 % below the limit: min_dt = 1e-3 is
//    0.17 % of it, and the plane-strain limit is reached only asymptotically (sigma_zz tends to
//    sigma_xx / 2 as the plastic strain grows without bound, so the load-displacement curve
//    flattens and a load step just below the limit needs a huge displacement increment):
//    measured, 0.575 converges and 0.576 fails (0.41 % below), so a cut-back that gave up early
//    or a limit off by a percent fails the check.
//  * A failing material update: verification/stability_compression.yaml squeezes a
//    neo-Hookean block to 40 % of its height in one load step; the first iterate inverts the
//    upper cell, the material update fails, and the step must be cut back and the run complete.
//    The recovered run took two half steps; it must end where a run started with half steps
//    (which never fails) ends, to 1e-6 in the top row's height: Newton's tolerance (1e-8 of the
//    force scale) bounds the difference far below that, and a state corrupted by the failed
//    attempt (trial history left behind) would be off by percents. (Not a run of 20 steps: the
//    prescribed box follows its displacement in whole cells, so the path matters.)
#include "cases.hpp"

#include "talus/io/case_reader.hpp"

#include <cmath>
#include <fmt/format.h>

namespace talus::verify_cases {

namespace {

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

/// Mean y of the points whose initial y is the largest, in the last frame.
double top_row_height(const ResultsReader& results) {
  Index rows = 0, cols = 0;
  const auto x0 = results.read(0, "position", &rows, &cols);
  const auto x1 = results.read(results.frame_count() - 1, "position", &rows, &cols);
  double top = -1e300;
  for (Index p = 0; p < rows; ++p)
    top = std::max(top, x0[static_cast<std::size_t>(2 * p + 1)]);
  double sum = 0;
  int n = 0;
  for (Index p = 0; p < rows; ++p)
    if (std::abs(x0[static_cast<std::size_t>(2 * p + 1)] - top) < 1e-12) {
      sum += x1[static_cast<std::size_t>(2 * p + 1)];
      ++n;
    }
  return sum / n;
}

} // namespace

VerificationCase stability_recovery() {
  VerificationCase vc;
  vc.name = "stability_recovery";
  vc.scene = "stability_plastic_tension";
  vc.description = "Implicit recovery: a von Mises block pulled to twice its plane-strain limit "
                   "load stops with exit 3 at the limit after cutting back; a neo-Hookean block "
                   "whose first Newton iterate inverts recovers by cutting back.";
  vc.tiers = {"stability"};
  vc.run = [](const VerificationContext& ctx) {
    std::vector<Check> checks;
    const auto tension_dir = ctx.out_dir / "past_limit";
    const RunResult t =
        run_case(load_verification_case(ctx), RunOptions{tension_dir, true, ctx.threads, false});
    checks.push_back(absolute_check("past the limit: exit code", t.exit_code, kExitNumerical, 0.0,
                                    t.message.substr(0, 240)));
    checks.push_back(holds_check("past the limit: message names the minimum load step",
                                 contains(t.message, "minimum load step")));
    const ResultsReader tension(tension_dir / "run.h5");
    const double last_factor = tension.frame_time(tension.frame_count() - 1);
    checks.push_back(relative_check("past the limit: last converged load / limit load",
                                    2.0 * last_factor, 2.0 / std::sqrt(3.0), 0.005,
                                    "limit 2/sqrt(3) sigma_y, load 2 sigma_y x factor"));
    checks.push_back(at_least_check("past the limit: cut-backs", t.extra.at("cutbacks"), 7.0,
                                    "dt 0.1 -> min_dt 1e-3 takes 7 halvings"));

    const auto compression =
        read_case_file((verification_dir() / "stability_compression.yaml").string(), {});
    const auto compression_dir = ctx.out_dir / "material_failure";
    const RunResult c = run_quiet(compression, compression_dir, ctx.threads);
    checks.push_back(at_least_check("material failure: cut-backs", c.extra.at("cutbacks"), 1.0,
                                    "the step of the inverted iterate is cut back"));
    checks.push_back(report_only("material failure: load steps", c.extra.at("load_steps")));
    const auto reference_dir = ctx.out_dir / "half_steps";
    run_quiet(read_case_file((verification_dir() / "stability_compression.yaml").string(),
                             {"time.dt=0.5"}),
              reference_dir, ctx.threads);
    checks.push_back(relative_check("material failure: top row height",
                                    top_row_height(ResultsReader(compression_dir / "run.h5")),
                                    top_row_height(ResultsReader(reference_dir / "run.h5")), 1e-12,
                                    "against a run started with half steps: after the cut-back "
                                    "the steps are the same, so round-off (measured: bitwise)"));
    return checks;
  };
  return vc;
}

} // namespace talus::verify_cases
