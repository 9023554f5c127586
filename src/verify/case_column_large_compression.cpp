// A soft column compressed by its own weight, the measure of how an interpolation copes with
// large deformation (issue 21). Hencky, implicit quasi-static; rollers on the sides and the
// base make the exact solution one-dimensional in the initial height Y:
//     sigma_yy(Y) = -rho0 g (H - Y)                 (the weight above, on an unchanged area),
//     M ln(lambda) / lambda = sigma_yy(Y)           (Hencky, uniaxial strain: tau = M ln lambda),
//     u(Y) = int_0^Y (lambda - 1) dY'.
// M = E (1 - nu) / ((1 + nu)(1 - 2 nu)). At rho g H / E = 4 the base is squeezed to 35 % of
// its height. Measures: the volume-weighted relative L2 error of the raw and the smoothed
// particle stress sigma_yy, and the top row's displacement, for each shape and resolution.
#include "cases.hpp"
#include "newton_log.hpp"

#include <cmath>
#include <fmt/format.h>
#include <map>
#include <tuple>

namespace talus::verify_cases {

namespace {

// The column is four cells wide at every resolution (the problem is one-dimensional; the
// cubic splines need three cells along each axis).
constexpr double kHeight = 1.0, kDensity = 1000.0, kGravity = 10.0, kPoisson = 0.3;

/// The stretch at initial height Y: the root of M ln(l) / l = sigma in (0, 1] (the left side
/// increases monotonically there), by bisection to round-off.
double exact_stretch(double Y, double E) {
  const double M = E * (1 - kPoisson) / ((1 + kPoisson) * (1 - 2 * kPoisson));
  const double sigma = -kDensity * kGravity * (kHeight - Y);
  double lo = 1e-6, hi = 1.0;
  for (int i = 0; i < 200 && hi - lo > 1e-16; ++i) {
    const double mid = 0.5 * (lo + hi);
    (M * std::log(mid) / mid > sigma ? hi : lo) = mid;
  }
  return 0.5 * (lo + hi);
}

/// u(Y) by composite Simpson's rule on 2000 intervals (lambda is smooth in Y).
double exact_displacement(double Y, double E) {
  const int n = 2000;
  const double dY = Y / n;
  double sum = 0;
  for (int i = 0; i <= n; ++i) {
    const double w = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
    sum += w * (exact_stretch(i * dY, E) - 1.0);
  }
  return sum * dY / 3.0;
}

struct ColumnErrors {
  double raw = 0, smoothed = 0; ///< relative L2 errors of sigma_yy
  double top = 0;               ///< the top row's displacement, relative error (signed)
};

ColumnErrors measure(const ResultsReader& results, double E) {
  Index rows = 0, dims = 0, cols = 0;
  const auto x0 = results.read(0, "position", &rows, &dims);
  const auto volume = results.read(0, "volume", &rows, &cols);
  const Index last = results.frame_count() - 1;
  const auto x = results.read(last, "position", &rows, &dims);
  const auto raw = results.read(last, "stress", &rows, &cols);
  const auto smoothed = results.read(last, "stress_smoothed", &rows, &cols);
  double raw_error = 0, smooth_error = 0, norm = 0, top = -1, top_u = 0;
  int top_count = 0;
  const auto D = static_cast<std::size_t>(dims), C = static_cast<std::size_t>(cols);
  for (Index p = 0; p < rows; ++p) {
    const auto s = static_cast<std::size_t>(p);
    const double Y = x0[D * s + 1];
    const double exact = -kDensity * kGravity * (kHeight - Y);
    raw_error += volume[s] * std::pow(raw[s * C + 3] - exact, 2); // xx, xy, xz, yy, ...
    smooth_error += volume[s] * std::pow(smoothed[s * C + 3] - exact, 2);
    norm += volume[s] * exact * exact;
    if (Y > top + 1e-9) {
      top = Y;
      top_u = 0;
      top_count = 0;
    }
    if (std::abs(Y - top) <= 1e-9) {
      top_u += x[D * s + 1] - Y;
      ++top_count;
    }
  }
  const double exact_top = exact_displacement(top, E);
  return {std::sqrt(raw_error / norm), std::sqrt(smooth_error / norm),
          (top_u / top_count - exact_top) / std::abs(exact_top)};
}

} // namespace

VerificationCase column_large_compression() {
  VerificationCase vc;
  vc.name = "column_large_compression";
  vc.description = "A soft Hencky column compressed by its own weight (rho g H / E = 0.04, 0.4, "
                   "4) for every shape: sigma_yy against -rho0 g (H - Y) and the top "
                   "displacement under refinement.";
  vc.tiers = {"fast", "full"};
  vc.run = [](const VerificationContext& ctx) {
    const std::vector<std::string> shapes = {"gimp", "cpgimp", "cpdi", "bspline2", "bspline3"};
    const std::vector<double> ratios = {0.04, 0.4, 4.0};
    const std::vector<int> cells = {8, 16, 32};
    std::map<std::tuple<double, std::string, int>, ColumnErrors> errors;
    std::vector<Check> checks;
    for (const double ratio : ratios)
      for (const auto& shape : shapes) {
        const double E = kDensity * kGravity * kHeight / ratio;
        for (const int n : cells) {
          const double h = kHeight / n;
          const CaseSpec spec = load_verification_case(
              ctx,
              {fmt::format("grid.cell_size={:.17g}", h),
               fmt::format("grid.extent=[{:.17g}, {:.17g}]", 4 * h, kHeight + 4 * h),
               fmt::format("bodies[0].max=[{:.17g}, {:.17g}]", 4 * h, kHeight),
               fmt::format("materials[0].youngs_modulus={:.17g}", E), "solver.shape=" + shape});
          const auto dir = ctx.out_dir / fmt::format("ratio{:g}_{}_cells{}", ratio, shape, n);
          run_quiet(spec, dir, ctx.threads);
          const ColumnErrors& e = errors[{ratio, shape, n}] =
              measure(ResultsReader(dir / "run.h5"), E);
          const std::string at = fmt::format("rho g H/E = {:g}, {}, H/{}", ratio, shape, n);
          // The figure (16 cells, 2 x 2 points per cell) is checked below.
          if (!(ratio == 4.0 && n == 16 && shape != "gimp"))
            checks.push_back(report_only("raw L2 sigma_yy, " + at, e.raw));
          checks.push_back(report_only("smoothed L2 sigma_yy, " + at, e.smoothed));
          checks.push_back(report_only("top displacement error, " + at, e.top));
        }
        const auto order = [&](int coarse, int fine, bool smoothed) {
          const ColumnErrors &a = errors[{ratio, shape, coarse}], &b = errors[{ratio, shape, fine}];
          return smoothed ? observed_order(a.smoothed, b.smoothed) : observed_order(a.raw, b.raw);
        };
        for (std::size_t i = 1; i < cells.size(); ++i) {
          const std::string q = fmt::format("order H/{} to H/{}, rho g H/E = {:g}, {}",
                                            cells[i - 1], cells[i], ratio, shape);
          const double raw = order(cells[i - 1], cells[i], false);
          if ((shape == "cpgimp" || shape == "cpdi") && ratio >= 0.4)
            // The domains tile the deformed column, so its quadrature stays as good as at
            // small strain: measured cpGIMP 1.57, 1.49 (0.4) and 1.38, 1.44 (4), CPDI 1.51,
            // 1.49 and 1.43, 1.38.
            checks.push_back(within_check("raw " + q, raw, 1.0, 2.0,
                                          "domains that follow the stretch keep the order"));
          else if (ratio == 0.04 && i == 2)
            // Small strain: every shape converges (measured 0.93 to 1.83; theory 1 for the
            // raw stress, which is read from the gradients).
            checks.push_back(within_check("raw " + q, raw, 0.7, 2.5, "small strain, theory 1"));
          else
            checks.push_back(report_only("raw " + q, raw));
          checks.push_back(report_only("smoothed " + q, order(cells[i - 1], cells[i], true)));
        }
      }
    // The measure: rho g H / E = 4, 16 cells, 2 x 2 points per cell. uGIMP's fixed
    // domains overlap where the column is squeezed (10.5 %); AMPLE's stretched GIMP reaches
    // 1.1 %. Each new shape within [1/3, 2.5] x its measured error (cpgimp 1.00 %, cpdi
    // 0.91 %, bspline2 1.35 %, bspline3 0.55 %), and the best at most the 1.5 %.
    const std::map<std::string, double> measured = {
        {"cpgimp", 0.0100}, {"cpdi", 0.0091}, {"bspline2", 0.0135}, {"bspline3", 0.00554}};
    double best = 1.0;
    std::string best_shape;
    for (const auto& [shape, value] : measured) {
      const double e = errors[{4.0, shape, 16}].raw;
      checks.push_back(within_check(fmt::format("raw L2 sigma_yy, rho g H/E = 4, {}, H/16", shape),
                                    e, value / 3, 2.5 * value,
                                    fmt::format("measured {:.2f} %; uGIMP 10.5 %", 100 * value)));
      if (e < best) {
        best = e;
        best_shape = shape;
      }
      // The top displacement: uGIMP -0.99 %; the new shapes measured -0.25 (cpgimp), +0.05
      // (cpdi), -0.41, -0.07 % (splines).
      checks.push_back(within_check(
          fmt::format("top displacement error, rho g H/E = 4, {}, H/16", shape),
          errors[{4.0, shape, 16}].top, -0.01, 0.01, "2.5 x the largest measured, 0.41 %"));
    }
    checks.push_back(
        at_most_check(fmt::format("best raw L2 sigma_yy at rho g H/E = 4, H/16 ({})", best_shape),
                      best, 0.015, "issue 21's target (AMPLE: 1.1 %)"));
    // cpGIMP's domain is set at the start of a load step and held through it, so the step's
    // consistent tangent needs no derivative of the domain: Newton stays quadratic.
    for (const auto& shape : shapes)
      checks.push_back(at_least_check(
          fmt::format("Newton's worst order, rho g H/E = 4, {}, H/32", shape),
          worst_newton_order(ctx.out_dir / fmt::format("ratio4_{}_cells32", shape) / "newton.log"),
          1.8, "quadratic convergence: the tangent is consistent"));
    return checks;
  };
  return vc;
}

} // namespace talus::verify_cases
