// The axially vibrating bar (verification/vibrating_bar.yaml, explicit MUSL) for every shape,
// measured by its stress: the first mode u = (v0 / w1) sin(b1 X) sin(w1 t) has
//     sigma_xx(X, t) = rho c v0 cos(b1 X) sin(w1 t),
// and the error is the RMS over all points and frames of sigma_p - sigma_xx(X_p, t_frame),
// relative to the amplitude rho c v0. The displacement stays below 2 % of a cell, so no point
// crosses a cell face: what is left is the grid's dispersion and the points' quadrature. The
// bar is three cells high (rollers above and below keep it one-dimensional) so that the cubic
// splines have their three cells on every axis.
//
// Theory: the raw point stress is read from the gradient of the interpolated velocity. Hats,
// uGIMP, cpGIMP and CPDI (the same here: the domains barely stretch) have a piecewise-constant
// gradient along a cell, so the stress converges at first order; the splines' gradients are
// continuous and piecewise linear (quadratic), second order. Measured (16, 32, 64 cells):
// linear 1.31e-2, 6.2e-3, 3.1e-3 (orders 1.08, 1.01), uGIMP and cpGIMP 1.31e-2, 6.1e-3,
// 3.25e-3 (1.10, 0.91), CPDI 1.31e-2, 6.1e-3, 2.99e-3 (1.11, 1.03),
// bspline2 1.21e-2, 3.8e-3, 8.0e-4 (1.66, 2.27), bspline3 1.56e-2, 3.7e-3, 9.8e-4 (2.06, 1.93).
// Checks: the finest order within [0.8, 1.3] (first order) or [1.7, 3] (second order or better: the
// issue's demand of the splines), two-sided so that a spline that lost its smoothness (order 1) or
// an error that stopped falling (0) fails; the error at 64 cells at most 2.5x its measured value.
#include "cases.hpp"
#include "references.hpp"

#include "talus/io/case_reader.hpp"

#include <cmath>
#include <fmt/format.h>
#include <map>
#include <numbers>

namespace talus::verify_cases {

using references::kBarDensity;
using references::kBarLength;
using references::kBarV0;
using references::kBarYoung;

namespace {

double stress_error(const ResultsReader& results) {
  const double b1 = std::numbers::pi / (2 * kBarLength);
  const double c = std::sqrt(kBarYoung / kBarDensity);
  const double omega = b1 * c;
  const double amplitude = kBarDensity * c * kBarV0;
  Index rows = 0, dims = 0, cols = 0;
  const auto x0 = results.read(0, "position", &rows, &dims);
  double sum = 0, count = 0;
  for (Index f = 1; f < results.frame_count(); ++f) {
    const double t = results.frame_time(f);
    const auto stress = results.read(f, "stress", &rows, &cols);
    for (Index p = 0; p < rows; ++p) {
      const double X = x0[static_cast<std::size_t>(p * dims)];
      const double exact = amplitude * std::cos(b1 * X) * std::sin(omega * t);
      sum += std::pow(stress[static_cast<std::size_t>(p * cols)] - exact, 2);
      count += 1;
    }
  }
  return std::sqrt(sum / count) / amplitude;
}

} // namespace

VerificationCase vibrating_bar_shapes() {
  VerificationCase vc;
  vc.name = "vibrating_bar_shapes";
  vc.distributable = true;
  vc.scene = "vibrating_bar";
  vc.description = "The fixed-free bar in its first axial mode for every shape (explicit MUSL): "
                   "RMS point stress against rho c v0 cos(b1 X) sin(w1 t) under refinement.";
  vc.tiers = {"fast", "full"};
  vc.run = [](const VerificationContext& ctx) {
    const std::vector<int> cells = {16, 32, 64};
    std::vector<Check> checks;
    for (const std::string shape : {"linear", "gimp", "cpgimp", "cpdi", "bspline2", "bspline3"}) {
      std::vector<double> errors;
      for (const int n : cells) {
        auto overrides = references::vibrating_bar_overrides(n, 2, 3);
        overrides.insert(overrides.end(), {"output.fields=[stress]", "solver.shape=" + shape});
        const CaseSpec spec = load_verification_case(ctx, overrides);
        const auto dir = ctx.out_dir / fmt::format("{}_cells{}", shape, n);
        run_quiet(spec, dir, ctx.threads);
        errors.push_back(stress_error(ResultsReader(dir / "run.h5")));
        if (n != cells.back())
          checks.push_back(report_only(fmt::format("{}: rms stress error, {} cells", shape, n),
                                       errors.back(), "relative to rho c v0"));
      }
      const bool spline = shape == "bspline2" || shape == "bspline3";
      checks.push_back(report_only(fmt::format("{}: order 16 to 32 cells", shape),
                                   observed_order(errors[0], errors[1])));
      checks.push_back(within_check(fmt::format("{}: order 32 to 64 cells", shape),
                                    observed_order(errors[1], errors[2]), spline ? 1.7 : 0.8,
                                    spline ? 3.0 : 1.3,
                                    spline ? "theory 2: continuous, piecewise-linear gradients"
                                           : "theory 1: piecewise-constant gradients"));
      const std::map<std::string, double> measured = {{"linear", 3.09e-3},   {"gimp", 3.25e-3},
                                                      {"cpgimp", 3.25e-3},   {"cpdi", 2.99e-3},
                                                      {"bspline2", 7.99e-4}, {"bspline3", 9.84e-4}};
      checks.push_back(at_most_check(fmt::format("{}: rms stress error at 64 cells", shape),
                                     errors[2], 2.5 * measured.at(shape), "2.5x measured"));
      if (shape == "linear" || shape == "gimp")
        continue; // their 3D bars: vibrating_bar_3d
      // The bar in 3D, three cells high and deep between rollers (nu = 0: no lateral coupling),
      // at 32 cells: the same discrete problem as in plane strain.
      auto overrides = references::vibrating_bar_overrides(32, 3, 3);
      overrides.insert(overrides.end(), {"output.fields=[stress]", "solver.shape=" + shape});
      const auto dir = ctx.out_dir / fmt::format("{}_3d_cells32", shape);
      run_quiet(read_case_file((verification_dir() / "vibrating_bar_3d.yaml").string(), overrides),
                dir, ctx.threads);
      const double error_3d = stress_error(ResultsReader(dir / "run.h5"));
      checks.push_back(relative_check(fmt::format("{}: 3D rms stress error, 32 cells", shape),
                                      error_3d, errors[1], 1e-10,
                                      "plane strain's; measured 1.4e-12 to 2e-11 (round-off)"));
    }
    return checks;
  };
  return vc;
}

} // namespace talus::verify_cases
