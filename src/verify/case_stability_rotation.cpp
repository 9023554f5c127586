// Large rotation: the rigid-rotation disc (verification/rigid_rotation.yaml: neo-Hookean, APIC,
// GIMP, R = 0.2 m, rho = 20) spun at one revolution per second for ten revolutions, with
// E = 2e3 Pa and cells of 0.05 m (200 points) so that the run stays short (c_p = 12 m/s, 4600
// steps; the centrifugal strain stays below 1 %). Objectivity: the only stress is the
// physical centrifugal one, static value (3 + nu) / 8 rho omega^2 R^2 = 13 Pa at the centre; a
// sudden release makes the fundamental mode overshoot to twice that, so the bound is 4x (as in
// the rigid_rotation case), while a non-objective update would reach E (1 - cos theta) ~ 2e3 Pa
// within a quarter turn. Energy bounded: the kinetic energy of the spin may only decay (APIC
// dissipates a little), never grow by more than the 1 %.
#include "cases.hpp"
#include "histories.hpp"

#include "talus/io/csv.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <numbers>

namespace talus::verify_cases {

VerificationCase stability_rotation() {
  VerificationCase vc;
  vc.name = "stability_rotation";
  vc.scene = "rigid_rotation";
  vc.description = "Neo-Hookean disc (APIC, GIMP) spinning for ten revolutions: stress stays at "
                   "the physical centrifugal level, energy does not grow.";
  vc.tiers = {"stability"};
  vc.run = [](const VerificationContext& ctx) {
    constexpr double kRevolutions = 10;
    const double omega = 2.0 * std::numbers::pi;
    const CaseSpec spec = load_verification_case(
        ctx, {"materials[0].youngs_modulus=2e3", "grid.cell_size=0.05",
              fmt::format("bodies[0].angular_velocity={:.17g}", omega),
              fmt::format("time.end_time={:g}", kRevolutions), "output.every_time=0.25"});
    const auto dir = ctx.out_dir / "run";
    run_quiet(spec, dir, ctx.threads);
    const auto& m = spec.materials[0];
    const auto& b = spec.bodies[0];
    const double centrifugal =
        (3.0 + m.poisson_ratio) / 8.0 * m.density * omega * omega * b.radius * b.radius;
    const ResultsReader results(dir / "run.h5");
    HistoryPlot plot;
    History stress{"max |sigma| / static centrifugal stress", "APIC, neo-Hookean", {}, {}};
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
    plot.add_column("E(t) / E(0) - 1", "APIC, neo-Hookean", series, "total_energy", true);
    plot.write(ctx.out_dir, "stability_rotation", "Spinning disc, 10 revolutions");
    const double peak = *std::max_element(energy.begin(), energy.end());
    return std::vector<Check>{
        bound_check("max |sigma| / static centrifugal", worst / centrifugal, 4.0,
                    "fundamental-mode overshoot 2, higher modes on top"),
        report_only("max |sigma| / E", worst / m.youngs_modulus,
                    "a non-objective update would reach ~1"),
        bound_check("max E(t)/E(0) - 1", peak / energy.front() - 1.0, 0.01, "no energy growth"),
        report_only("E(end)/E(0) - 1", energy.back() / energy.front() - 1.0,
                    "APIC dissipation over ten revolutions"),
        report_only("revolutions", kRevolutions)};
  };
  return vc;
}

} // namespace talus::verify_cases
