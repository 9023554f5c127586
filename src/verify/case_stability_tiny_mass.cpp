// Tiny-mass nodes: points that barely reach a node (placement.offset shifts the point lattice by
// a hair, see verification/stability_tiny_mass.yaml).
//  * Explicit: the vibrating block with linear hats (offset -0.49998 spacing: the right column
//    and top row sit 1e-5 h past a node line, so the next nodes get 1e-5 of a point's weight),
//    and with GIMP (offset 2e-4: the point domains reach 1e-4 h into the next cells, weight
//    1e-8), both under MUSL (the default). No blow-up: the runs complete, and the peak energy
//    exceeds that of the same points shifted so that no node is barely touched (linear: offset
//    -0.4, weight 5e-2; GIMP: the regular lattice) by at most 2e-3 of E(0) either way for
//    linear hats (3.5x the measured 5.7e-4) and 5e-6 for GIMP (4x the measured 1.3e-6; its
//    regular run differs by a shift of 1e-4 h only): a tiny-mass node that adds energy, or one
//    that damps the block, fails. Both runs show the
//    same per-step oscillation of ~omega dt / 2 from the half-step staggering of kinetic and
//    strain energy (see stability_explicit_cfl), with slightly different phases (the points sit
//    differently in their cells), so peaks are compared, not histories; a tiny-mass node whose
//    velocity were force / tiny mass would add energy at once. Linear hats under USL and USF,
//    which update the stress with the velocity of the tiny-mass node itself (force / tiny mass
//    times dt, not remapped from the points as MUSL does), are the known limit of
//    docs/case-format.md: there the run must stop with exit 3 and the guard's message naming the
//    point, never carry NaN on (measured: USL stops at step 3, USF at step ~420).
//  * Implicit: the verification cantilever (8 cells through the depth, GIMP, linear elastic,
//    P = 1) with the tip column and top row reaching 1e-4 h (weights 1e-8, kept and regularised by
//    the ghost penalty) and 1e-6 h (weights 1e-12, below the solver's 1e-10 cut, removed) past a
//    node line. Newton must converge in at most 2 iterations (the problem is linear up to the
//    geometric terms of a 1e-3 rotation: measured 1; an ill-conditioned solve needs more) and
//    the tip deflection must stay within the cantilever verification's 0.2 % of
//    Timoshenko-Goodier (measured 0.06 %, the regular lattice's error).
#include "cases.hpp"
#include "histories.hpp"
#include "references.hpp"

#include "talus/core/errors.hpp"
#include "talus/io/case_reader.hpp"
#include "talus/io/csv.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>

namespace talus::verify_cases {

namespace {

/// max_t E(t) / E(0) - 1 of a timeseries.
double peak_growth(const CsvTable& series) {
  const auto& e = series.column("total_energy");
  return *std::max_element(e.begin(), e.end()) / e.front() - 1.0;
}

} // namespace

VerificationCase stability_tiny_mass() {
  VerificationCase vc;
  vc.name = "stability_tiny_mass";
  vc.description = "Points barely reaching a node (weights 1e-5 to 1e-12): an explicit "
                   "vibrating block (MUSL with linear hats and GIMP) stays bounded, linear USL/USF "
                   "stop with exit 3; the implicit cantilever's Newton converges with the "
                   "deflection within 1 %.";
  vc.tiers = {"stability"};
  vc.run = [](const VerificationContext& ctx) {
    std::vector<Check> checks;
    HistoryPlot plot;
    struct Explicit {
      const char* label;
      const char* shape;
      const char* scheme;
      const char* offset;
      const char* regular_offset; ///< the same points, none barely touching a node
      double bound;               ///< on the peak energy's difference from the regular run
    };
    for (const Explicit& e : {Explicit{"linear, musl", "linear", "musl", "-0.49998", "-0.4", 2e-3},
                              Explicit{"gimp, musl", "gimp", "musl", "2e-4", "0", 5e-6},
                              Explicit{"linear, usl", "linear", "usl", "-0.49998", "", 0},
                              Explicit{"linear, usf", "linear", "usf", "-0.49998", "", 0}}) {
      const auto dir = ctx.out_dir / fmt::format("explicit_{}_{}", e.shape, e.scheme);
      const CaseSpec spec = load_verification_case(
          ctx, {fmt::format("solver.shape={}", e.shape), fmt::format("solver.scheme={}", e.scheme),
                fmt::format("bodies[0].placement.offset=[{0}, {0}]", e.offset)});
      if (std::string(e.scheme) != "musl") {
        const RunResult r = run_case(spec, RunOptions{dir, true, ctx.threads, false});
        const bool stopped_clearly = r.exit_code == kExitNumerical &&
                                     r.message.find("state guard") != std::string::npos &&
                                     r.message.find("particle") != std::string::npos;
        checks.push_back(holds_check(fmt::format("explicit {}: stopped by the guard", e.label),
                                     stopped_clearly,
                                     r.exit_code == 0 ? "completed: the tiny-mass node went unseen"
                                                      : r.message.substr(0, 200)));
        checks.push_back(report_only(fmt::format("explicit {}: steps before the stop", e.label),
                                     static_cast<double>(r.steps), "known limit of linear hats"));
        continue;
      }
      run_quiet(spec, dir, ctx.threads);
      const auto regular_dir = dir.string() + "_regular";
      run_quiet(load_verification_case(
                    ctx, {fmt::format("solver.shape={}", e.shape),
                          fmt::format("solver.scheme={}", e.scheme),
                          fmt::format("bodies[0].placement.offset=[{0}, {0}]", e.regular_offset)}),
                regular_dir, ctx.threads);
      const CsvTable series = read_csv(dir / "timeseries.csv");
      const CsvTable regular = read_csv(std::filesystem::path(regular_dir) / "timeseries.csv");
      checks.push_back(
          within_check(fmt::format("explicit {}: peak E/E(0), tiny-mass - regular", e.label),
                       peak_growth(series) - peak_growth(regular), -e.bound, e.bound,
                       fmt::format("completed; peak E/E(0) - 1 = {:.4g} against {:.4g}",
                                   peak_growth(series), peak_growth(regular))));
      plot.add_column("explicit block: E(t) / E(0) - 1", e.label, series, "total_energy", true);
      plot.add_column("explicit block: E(t) / E(0) - 1", std::string(e.label) + ", regular",
                      regular, "total_energy", true);
    }
    for (const double reach : {1e-4, 1e-6}) {
      // The lattice offset (in spacings h / 2) that puts the outer points' domains `reach` h
      // past the next node's support.
      const double offset = 2.0 * reach;
      const CaseSpec spec =
          read_case_file((verification_dir() / "cantilever.yaml").string(),
                         {fmt::format("bodies[0].placement.offset=[{0:g}, {0:g}]", offset)});
      const auto dir = ctx.out_dir / fmt::format("implicit_reach_{:g}", reach);
      const RunResult r = run_quiet(spec, dir, ctx.threads);
      double x = 0;
      const Vec3 u = references::tip_column_displacement(ResultsReader(dir / "run.h5"), &x);
      const std::string at =
          fmt::format("implicit, reach {:g} h (weight {:g})", reach, reach * reach);
      checks.push_back(relative_check(at + ": tip deflection", u.y(),
                                      references::cantilever_deflection(x, 1.0), 0.002,
                                      "Timoshenko-Goodier, as the cantilever case"));
      checks.push_back(at_most_check(at + ": Newton iterations", r.extra.at("newton_iterations"),
                                     2.0, "nearly linear problem: one iteration (measured)"));
    }
    plot.write(ctx.out_dir, "stability_tiny_mass", "Tiny-mass nodes");
    return checks;
  };
  return vc;
}

} // namespace talus::verify_cases
