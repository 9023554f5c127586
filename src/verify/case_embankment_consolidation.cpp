// An embankment on soft clay built faster than the clay drains (verification/
// embankment_consolidation.yaml, the case cases/embankment_on_soft_clay.yaml): q = 50 kPa over a
// half-width of 4 m put on in 10 days on 8 m of clay (c' = 5 kPa, phi' = 25 deg, psi = 0,
// E' = 5 MPa, k = 1e-9 m/s: c_v = 6.9e-7 m^2/s, T_v = 1 after 3 years), then held for 10 years;
// `talus fos` searches the factor of safety after each stage from the state it left, undrained.
//
// Checks and why these bounds. The construction is undrained (T_v = 2e-4 at its end): under the
// centre 2 m deep the water carries at least the elastic undrained mean stress, 0.75 q (a
// strip 8 m wide: sigma_z = 0.96 q, sigma_x = 0.55 q, nu_u = 1/2), and at most the load and a
// tenth; measured 1.01 q. The excess dissipates: after 10 years (T_v = 3.4, the series leaves
// 2e-4 of it) the excess under the centre should be below 0.02 q; measured up to 0.13 q, a
// known failure: it stops falling after about 4 years (below). As it drains the clay gains
// effective stress and strength: the factor never falls from one stage to the next by more than the
// search's tolerance, and rises by at least 0.3 in all (measured 1.18 to 1.79).
#include "cases.hpp"
#include "talus/io/results.hpp"
#include "talus/solver/strength_reduction.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace talus::verify_cases {

namespace {

constexpr double kLoad = 5.0e4;     ///< q, Pa
constexpr double kSurface = 8.0;    ///< m, the clay's surface and the water table
constexpr double kGammaW = 9810.0;  ///< N/m^3
constexpr double kCentreX = 0.25;   ///< m, the column of points under the load's centre
constexpr double kProbeDepth = 2.0; ///< m below the surface

/// The excess pore pressure over q of the points in the column under the load's centre at the
/// end of a stage's history: at kProbeDepth, and the largest over the column.
struct CentreExcess {
  double at_depth = 0, largest = 0;
};

CentreExcess centre_excess(const std::filesystem::path& run, double history_end) {
  const ResultsReader results(run / "run.h5");
  Index frame = -1;
  for (Index k = 0; k < results.frame_count(); ++k)
    if (std::abs(results.frame_time(k) - history_end) <= 1e-9 * history_end)
      frame = k;
  if (frame < 0)
    throw NumericalError(fmt::format("'{}' holds no frame at the history's end, t = {:g} s",
                                     run.string(), history_end));
  Index rows = 0, dims = 0, cols = 0;
  const std::vector<double> position = results.read(frame, "position", &rows, &dims);
  const std::vector<double> p = results.read(frame, "pore_pressure", &rows, &cols);
  const auto d = static_cast<std::size_t>(dims);
  CentreExcess out;
  double nearest = 1e30;
  bool any = false;
  for (std::size_t s = 0; s < p.size(); ++s) {
    const double x = position[d * s], y = position[d * s + 1];
    if (std::abs(x - kCentreX) > 0.2 || y > kSurface)
      continue;
    any = true;
    const double excess = (p[s] - kGammaW * (kSurface - y)) / kLoad;
    out.largest = std::max(out.largest, std::abs(excess));
    if (const double gap = std::abs(y - (kSurface - kProbeDepth)); gap < nearest) {
      nearest = gap;
      out.at_depth = excess;
    }
  }
  if (!any)
    throw NumericalError("no clay point under the load's centre");
  return out;
}

} // namespace

VerificationCase embankment_consolidation() {
  VerificationCase vc;
  vc.name = "embankment_consolidation";
  vc.description = "An embankment load on soft clay put on faster than the clay drains: the "
                   "undrained excess pore pressure under it, its dissipation over 10 years, and "
                   "the factor of safety after each stage rising as the clay consolidates.";
  vc.tiers = {"full"};
  vc.run = [](const VerificationContext& ctx) {
    const CaseSpec spec = load_verification_case(ctx);
    const FosRunResult r = bracketed_search(ctx, spec, "search");
    const std::vector<StageFactorOfSafety>& h = r.history;
    if (h.size() != spec.stages.size())
      throw NumericalError(fmt::format("{} of {} stages searched", h.size(), spec.stages.size()));
    std::vector<Check> checks;
    const auto trials = ctx.out_dir / "search" / "trials";
    const CentreExcess built = centre_excess(trials / ("after_" + h.front().stage), h.front().time);
    const CentreExcess drained = centre_excess(trials / ("after_" + h.back().stage), h.back().time);
    checks.push_back(within_check(
        fmt::format("excess pore pressure / q, {:g} m under the centre, end of construction",
                    kProbeDepth),
        built.at_depth, 0.75, 1.1,
        "undrained: at least the elastic mean stress, at most q + 10 %"));
    checks.push_back(known_failure(
        at_most_check("largest excess pore pressure / q under the centre after 10 years",
                      drained.largest, 0.02, "T_v = 3.4: the series leaves 2e-4"),
        "the excess under the load stops dissipating: 2 m under the centre it falls from 1.0 q "
        "to 0.09 q by 4 years and stays there to 10 years (up to 0.6 q at the load's edge); "
        "cause not yet found"));
    double drop = 0;
    for (std::size_t k = 1; k < h.size(); ++k)
      drop = std::max(drop, h[k - 1].fos.value() - h[k].fos.value());
    checks.push_back(at_most_check("largest fall of the factor from one stage to the next", drop,
                                   spec.strength_reduction->tolerance,
                                   "the clay only gains strength as it drains"));
    checks.push_back(at_least_check(
        "factor after 10 years minus that after construction",
        h.back().fos.value() - h.front().fos.value(), 0.3,
        fmt::format("measured {:.3f} -> {:.3f}", h.front().fos.value(), h.back().fos.value())));
    for (const StageFactorOfSafety& s : h)
      checks.push_back(
          report_only(fmt::format("factor of safety after '{}' (t = {:.3g} s)", s.stage, s.time),
                      s.fos.value()));
    return checks;
  };
  return vc;
}

} // namespace talus::verify_cases
