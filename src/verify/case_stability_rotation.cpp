// Large rotation: the rigid-rotation disc (verification/rigid_rotation.yaml: neo-Hookean, APIC,
// GIMP, R = 0.2 m, rho = 20) spun at one revolution per second for ten revolutions, with
// E = 2e3 Pa and cells of 0.05 m (200 points) so that the run stays short (c_p = 12 m/s, 4600
// steps; the centrifugal strain stays below 1 %). Both transfers run: APIC (the scene's) and
// FLIP (pure, flip = 1).
//  * Objectivity: the only stress is the physical centrifugal one, static value
//    (3 + nu) / 8 rho omega^2 R^2 = 13 Pa at the centre, about which the suddenly released disc
//    oscillates between 0 and twice it: the largest stress over 40 frames must lie in [1, 4]x
//    that (as in the rigid_rotation case), while a non-objective update would reach
//    E (1 - cos theta) ~ 2e3 Pa within a quarter turn. APIC meets it (measured 2.0x); FLIP does
//    not (27x: its projection of a spin is inexact at the disc's edge), a known failure.
//  * Energy: an elastic spinning disc keeps its energy. No growth above 0.5 % (measured APIC
//    0.14 %, FLIP 0.11 %). The loss is bounded too: APIC within 1.5 % over the ten turns
//    (measured 0.42 %, 3.5x; it was 40 % while its F increment ignored the points' spread, see
//    solver/explicit_solver.cpp); FLIP, whose transfers dissipate at the edge, must keep at
//    least 70 % (measured 85 %: 2x the measured loss).
//  * Angular momentum: APIC's transfers conserve the total angular momentum, points' and affine
//    part; the points' part L = sum m (x - c) x v, the only one in the output, moves only with
//    the affine share as the spin changes: L(end)/L(0) within 1e-3 of 1 (measured 1 + 2.8e-4).
//    FLIP's transfers do not conserve it (Jiang et al. 2015): reported (measured 0.17).
#include "cases.hpp"
#include "histories.hpp"

#include "talus/io/csv.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <numbers>

namespace talus::verify_cases {

namespace {

/// Angular momentum of the points about their centre of mass in one frame (plane, z component).
double angular_momentum(const ResultsReader& results, Index frame) {
  Index rows = 0, cols = 0;
  const auto x = results.read(frame, "position", &rows, &cols);
  const auto v = results.read(frame, "velocity", &rows, &cols);
  const auto m = results.read(frame, "mass", &rows, &cols);
  Vec2 centre = Vec2::Zero();
  double mass = 0;
  for (Index p = 0; p < rows; ++p) {
    const auto s = static_cast<std::size_t>(p);
    centre += m[s] * Vec2(x[2 * s], x[2 * s + 1]);
    mass += m[s];
  }
  centre /= mass;
  double L = 0;
  for (Index p = 0; p < rows; ++p) {
    const auto s = static_cast<std::size_t>(p);
    L += m[s] * ((x[2 * s] - centre.x()) * v[2 * s + 1] - (x[2 * s + 1] - centre.y()) * v[2 * s]);
  }
  return L;
}

} // namespace

VerificationCase stability_rotation() {
  VerificationCase vc;
  vc.name = "stability_rotation";
  vc.scene = "rigid_rotation";
  vc.description = "Neo-Hookean disc (GIMP, APIC and FLIP) spinning for ten revolutions: "
                   "stress stays at the physical centrifugal level, energy does not grow.";
  vc.tiers = {"stability"};
  vc.run = [](const VerificationContext& ctx) {
    constexpr double kRevolutions = 10;
    const double omega = 2.0 * std::numbers::pi;
    const std::vector<std::string> overrides = {
        "materials[0].youngs_modulus=2e3", "grid.cell_size=0.05",
        fmt::format("bodies[0].angular_velocity={:.17g}", omega),
        fmt::format("time.end_time={:g}", kRevolutions), "output.every_time=0.25"};
    const CaseSpec spec = load_verification_case(ctx, overrides);
    const auto& m = spec.materials[0];
    const auto& b = spec.bodies[0];
    const double centrifugal =
        (3.0 + m.poisson_ratio) / 8.0 * m.density * omega * omega * b.radius * b.radius;
    HistoryPlot plot;
    std::vector<Check> checks;
    for (const std::string transfer : {"apic", "flip"}) {
      const auto dir = ctx.out_dir / transfer;
      auto with_transfer = overrides;
      with_transfer.push_back("solver.transfer=" + transfer);
      run_quiet(load_verification_case(ctx, with_transfer), dir, ctx.threads);
      const ResultsReader results(dir / "run.h5");
      const std::string label = transfer == "apic" ? "APIC" : "FLIP";
      History stress{"max |sigma| / static centrifugal stress", label, {}, {}};
      double worst = 0;
      for (Index f = 0; f < results.frame_count(); ++f) {
        Index rows = 0, cols = 0;
        double frame_max = 0;
        for (double s : results.read(f, "stress", &rows, &cols))
          frame_max = std::max(frame_max, std::abs(s));
        stress.x.push_back(results.frame_time(f));
        stress.y.push_back(frame_max / centrifugal);
        worst = std::max(worst, frame_max);
      }
      plot.add(std::move(stress));
      const CsvTable series = read_csv(dir / "timeseries.csv");
      const auto& energy = series.column("total_energy");
      plot.add_column("E(t) / E(0) - 1", label, series, "total_energy", true);
      const double peak = *std::max_element(energy.begin(), energy.end());
      const bool apic = transfer == "apic";
      const Check stress_check =
          within_check(label + ": max |sigma| / static centrifugal", worst / centrifugal, 1.0, 4.0,
                       "oscillation about the static state");
      checks.push_back(apic ? stress_check
                            : known_failure(stress_check,
                                            "FLIP projects a spin inexactly at the body's edge, "
                                            "which strains the edge"));
      checks.push_back(at_most_check(label + ": max E(t)/E(0) - 1", peak / energy.front() - 1.0,
                                     0.005, "no energy growth"));
      const double change = energy.back() / energy.front() - 1.0;
      checks.push_back(apic ? within_check(label + ": E(end)/E(0) - 1", change, -0.015, 0.005,
                                           "an elastic spin keeps its energy; 3.5x measured")
                            : within_check(label + ": E(end)/E(0) - 1", change, -0.3, 0.005,
                                           "FLIP's transfers dissipate: 2x the measured loss"));
      const double momentum =
          angular_momentum(results, results.frame_count() - 1) / angular_momentum(results, 0);
      checks.push_back(apic
                           ? within_check(label + ": angular momentum L(end)/L(0)", momentum, 0.999,
                                          1.001, "points' part; conserved up to the affine share")
                           : report_only(label + ": angular momentum L(end)/L(0)", momentum,
                                         "FLIP's transfers do not conserve it"));
    }
    plot.write(ctx.out_dir, "stability_rotation", "Spinning disc, 10 revolutions");
    checks.push_back(report_only("revolutions", kRevolutions));
    return checks;
  };
  return vc;
}

} // namespace talus::verify_cases
