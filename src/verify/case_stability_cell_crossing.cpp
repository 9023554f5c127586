// Cell crossing: verification/stability_cell_crossing.yaml, a free-free bar in its first axial
// mode translating across 32 cells, against the exact stress
// sigma_xx(X, t) = -rho c v0 sin(pi X / L) sin(w t). The error measure is the RMS over all
// points and all frames of sigma_p - sigma_exact(X_p, t), relative to the amplitude rho c v0.
// The same bar at rest (v_t = 0) gives the error without crossings; the difference is the
// crossing noise. Bounds:
//  * GIMP: the weights and gradients are continuous in the point's position, so crossing a
//    cell edge changes them by O(dt v_t / h) per step and adds no jump; at rest the error is the
//    bar's discretisation error (phase error w t (pi h / L)^2 / 24 ~ 1e-3 plus the O(h^2) stress
//    sampling error at the points). We require the translating GIMP error to stay below 2 % of
//    the amplitude (2.3x the measured 0.86 %) and at most 1.2x its own at-rest error (2x the
//    measured ratio 0.61: translating, the points sample every position within a cell and
//    their quadrature errors average out); a discontinuous-gradient scheme fails both by an
//    order of magnitude.
//  * cpGIMP, CPDI, quadratic and cubic B-splines (issue 21): their gradients are continuous
//    too; the translating error at most 2 % and at most 2x the one at rest (measured: cpGIMP
//    0.85 %, ratio 0.60; CPDI 0.91 %, 0.70; bspline2 1.14 %, 1.01; bspline3 1.51 %, 1.04). The
//    splines are run on a grid three cells high (they need three cells per axis; the bar's response
//    is one-dimensional).
//  * Linear hats: their gradient jumps by 1/h as a point crosses a node, which is the noise the
//    issue asks to quantify; the errors are reported, and as a control the translating error
//    must be at least 10x the one at rest (measured 48x): the bar really crosses cells, so the
//    GIMP bounds above test what they claim.
#include "cases.hpp"
#include "histories.hpp"

#include <cmath>
#include <fmt/format.h>
#include <numbers>

namespace talus::verify_cases {

namespace {

constexpr double kLength = 10, kStart = 1.25, kDensity = 1, kWaveSpeed = 10, kV0 = 0.1;

/// Relative RMS stress error over all frames, and its history (per-frame RMS).
double stress_error(const ResultsReader& results, History& history) {
  const double omega = std::numbers::pi * kWaveSpeed / kLength;
  const double amplitude = kDensity * kWaveSpeed * kV0;
  Index rows = 0, cols = 0;
  const auto x0 = results.read(0, "position", &rows, &cols);
  double sum = 0;
  double count = 0;
  for (Index f = 0; f < results.frame_count(); ++f) {
    const double t = results.frame_time(f);
    const auto stress = results.read(f, "stress", &rows, &cols);
    double frame_sum = 0;
    for (Index p = 0; p < rows; ++p) {
      const double X = x0[static_cast<std::size_t>(2 * p)] - kStart;
      const double exact =
          -amplitude * std::sin(std::numbers::pi * X / kLength) * std::sin(omega * t);
      const double e = stress[static_cast<std::size_t>(p * cols)] - exact;
      frame_sum += e * e;
    }
    sum += frame_sum;
    count += static_cast<double>(rows);
    history.x.push_back(t);
    history.y.push_back(std::sqrt(frame_sum / static_cast<double>(rows)) / amplitude);
  }
  return std::sqrt(sum / count) / amplitude;
}

} // namespace

VerificationCase stability_cell_crossing() {
  VerificationCase vc;
  vc.name = "stability_cell_crossing";
  vc.description = "A vibrating free-free bar translating across 32 cells: RMS stress error "
                   "against the exact mode for every shape, moving and at rest.";
  vc.tiers = {"stability"};
  vc.run = [](const VerificationContext& ctx) {
    std::vector<Check> checks;
    HistoryPlot plot({"RMS stress error / rho c v0"});
    for (const std::string shape : {"linear", "gimp", "cpgimp", "cpdi", "bspline2", "bspline3"}) {
      double errors[2] = {0, 0};
      for (const bool moving : {false, true}) {
        std::vector<std::string> overrides = {"solver.shape=" + shape};
        if (shape == "bspline2" || shape == "bspline3") // three cells high (1D all the same)
          overrides.insert(overrides.end(),
                           {"grid.extent=[22.5, 0.9375]", "bodies[0].max=[11.25, 0.9375]"});
        if (!moving)
          overrides.push_back("bodies[0].velocity=[\"0.1 * cos(pi / 10 * (x - 1.25))\", 0]");
        const auto dir = ctx.out_dir / fmt::format("{}_{}", shape, moving ? "moving" : "rest");
        run_quiet(load_verification_case(ctx, overrides), dir, ctx.threads);
        History h{"RMS stress error / rho c v0",
                  fmt::format("{}, {}", shape, moving ? "v_t = 2 m/s" : "at rest"),
                  {},
                  {}};
        errors[moving ? 1 : 0] = stress_error(ResultsReader(dir / "run.h5"), h);
        plot.add(std::move(h));
      }
      checks.push_back(report_only(shape + ": stress error at rest", errors[0],
                                   "RMS over points and frames / rho c v0"));
      if (shape == "gimp") {
        checks.push_back(at_most_check("gimp: stress error translating", errors[1], 0.02,
                                       "32 cells crossed; continuous gradients"));
        checks.push_back(at_most_check("gimp: error translating / at rest", errors[1] / errors[0],
                                       1.2, "crossing adds no jump"));
      } else if (shape != "linear") {
        checks.push_back(at_most_check(shape + ": stress error translating", errors[1], 0.02,
                                       "as uGIMP; measured 0.85 to 1.5 %"));
        checks.push_back(at_most_check(shape + ": error translating / at rest",
                                       errors[1] / errors[0], 2.0,
                                       "issue 21's bound; measured 0.60 to 1.04"));
      } else {
        checks.push_back(report_only("linear: stress error translating", errors[1],
                                     "gradient jumps at every crossing"));
        checks.push_back(at_least_check("linear: error translating / at rest",
                                        errors[1] / errors[0], 10.0,
                                        "control: the bar crosses cells and jumps show"));
      }
    }
    plot.write(ctx.out_dir, "stability_cell_crossing",
               "Vibrating bar translating across 32 cells: stress error");
    return checks;
  };
  return vc;
}

} // namespace talus::verify_cases
