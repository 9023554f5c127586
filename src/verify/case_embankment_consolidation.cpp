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
// 2e-4 of it) the water there is at rest, hydrostatic from the drained top above it, which is
// the fill's top (0.4 m above the table: the fill's pores are full of water); within 0.03 q,
// the top's place known to a quarter of the points' spacing (0.0125 q); measured 0.011 q. As it
// drains the clay gains effective stress and strength: the factor never falls from one stage
// to the next by more than the search's tolerance, and rises by at least 0.3 in all (measured
// 1.18 to 1.79). Broken on purpose: with no flow in the history the factor falls by 0.22 from
// one stage to the next and ends 0.17 below its start, and the water never comes to rest.
#include "cases.hpp"
#include "talus/io/results.hpp"
#include "talus/solver/strength_reduction.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

namespace talus::verify_cases {

namespace {

constexpr double kLoad = 5.0e4;     ///< q, Pa
constexpr double kSurface = 8.0;    ///< m, the clay's surface and the water table
constexpr double kGammaW = 9810.0;  ///< N/m^3
constexpr double kCentreX = 0.25;   ///< m, the column of points under the load's centre
constexpr double kProbeDepth = 2.0; ///< m below the surface
/// m, half the points' spacing (two per cell of 0.5 m): a drained surface lies this far above
/// its top row of points.
constexpr double kHalfSpacing = 0.125;

/// The pore pressure over q of the points in the column under the load's centre at the end of
/// a stage's history, less that of water at rest below `water_top` (the table's level, or the
/// drained top of the column): at kProbeDepth below the clay's surface, and the largest in the
/// clay.
struct CentreExcess {
  double at_depth = 0, largest = 0;
  double column_top = 0; ///< m, the highest point of the column (the fill's) plus half a spacing
};

CentreExcess centre_excess(const std::filesystem::path& run, double history_end,
                           std::optional<double> water_top) {
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
  const auto in_column = [&](std::size_t s) { return std::abs(position[d * s] - kCentreX) <= 0.2; };
  CentreExcess out;
  out.column_top = -1e30;
  for (std::size_t s = 0; s < p.size(); ++s)
    if (in_column(s))
      out.column_top = std::max(out.column_top, position[d * s + 1] + kHalfSpacing);
  const double top = water_top.value_or(out.column_top);
  double nearest = 1e30;
  bool any = false;
  for (std::size_t s = 0; s < p.size(); ++s) {
    const double y = position[d * s + 1];
    if (!in_column(s) || y > kSurface)
      continue;
    any = true;
    const double excess = (p[s] - kGammaW * (top - y)) / kLoad;
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
    // The excess of the undrained construction over the water at rest it started from; the
    // water's rest after consolidation is hydrostatic from the drained top of the column, the
    // fill's, whose pores are full of water like every material's in consolidation.
    const CentreExcess built =
        centre_excess(trials / ("after_" + h.front().stage), h.front().time, kSurface);
    const CentreExcess drained =
        centre_excess(trials / ("after_" + h.back().stage), h.back().time, std::nullopt);
    checks.push_back(within_check(
        fmt::format("excess pore pressure / q, {:g} m under the centre, end of construction",
                    kProbeDepth),
        built.at_depth, 0.75, 1.1,
        "undrained: at least the elastic mean stress, at most q + 10 %"));
    checks.push_back(at_most_check(
        fmt::format("|p - water at rest| / q, {:g} m under the centre, after 10 years",
                    kProbeDepth),
        std::abs(drained.at_depth), 0.03,
        fmt::format("T_v = 3.4: the series leaves 2e-4; the drained top at y = {:.3f} is known "
                    "to a quarter of a spacing, 0.0125 q",
                    drained.column_top)));
    checks.push_back(report_only("largest |p - water at rest| / q in the column after 10 years",
                                 drained.largest, "the points next to the drained top"));
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
