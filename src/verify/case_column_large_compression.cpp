// A soft column compressed by its own weight, the measure of how an interpolation copes with
// large deformation (issue 21). Hencky, implicit quasi-static; rollers on the sides and the
// base make the exact solution one-dimensional in the initial height Y (references.hpp):
// sigma_yy(Y) = -rho0 g (H - Y), M ln(lambda) / lambda = sigma_yy, u(Y) = int (lambda - 1). At rho
// g H / E = 4 the base is squeezed to 35 % of its height. Measures: the volume-weighted relative L2
// error of the raw and the smoothed particle stress sigma_yy, and the top row's displacement, for
// each shape and resolution.
#include "cases.hpp"
#include "newton_log.hpp"
#include "references.hpp"

#include "talus/io/case_reader.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <limits>
#include <map>
#include <tuple>

namespace talus::verify_cases {

using references::ColumnErrors;

namespace {

/// The raw stress tensors of every point in the last frame.
std::vector<double> final_stress(const std::filesystem::path& dir) {
  const ResultsReader results(dir / "run.h5");
  Index rows = 0, cols = 0;
  return results.read(results.frame_count() - 1, "stress", &rows, &cols);
}

/// Largest |sigma_axisymmetric - sigma_plane_strain| / (rho g H) over the points of the column
/// at n cells, both without the ghost penalty (its faces weigh by r in axisymmetry; see
/// axisymmetric_cylinder).
double axisymmetric_difference(const VerificationContext& ctx, const std::string& shape, int n,
                               double ratio) {
  auto overrides = references::compressed_column_overrides(n, ratio);
  overrides.insert(overrides.end(), {"solver.shape=" + shape, "solver.ghost_penalty=0"});
  const auto plane_dir = ctx.out_dir / fmt::format("plane_no_ghost_{}_cells{}", shape, n);
  run_quiet(read_case_file(ctx.case_file.string(), overrides), plane_dir, ctx.threads);
  overrides.push_back("geometry=axisymmetric");
  const auto axi_dir = ctx.out_dir / fmt::format("axisymmetric_{}_cells{}", shape, n);
  run_quiet(read_case_file(ctx.case_file.string(), overrides), axi_dir, ctx.threads);
  const auto a = final_stress(axi_dir), b = final_stress(plane_dir);
  if (a.size() != b.size()) // not the same points: nothing to compare, so the row must fail
    return std::numeric_limits<double>::infinity();
  double worst = 0;
  for (std::size_t k = 0; k < a.size(); ++k)
    worst = std::max(worst, std::abs(a[k] - b[k]));
  return worst /
         (references::kColumnDensity * references::kColumnGravity * references::kColumnHeight);
}

/// The same column at rho g H / E = 4 in 3D between four rollers and as a cylinder on rollers
/// (axisymmetry), against plane strain, for every shape. The problem is the same
/// one-dimensional one. uGIMP, cpGIMP and CPDI (whose voxels stay boxes here) integrate the
/// lateral and hoop terms of a laterally uniform state exactly with 2 points per cell (their
/// weights are piecewise linear across the points), so the discrete solutions agree to the
/// Newton tolerance: 3D measured 1.2e-11, 5.7e-11, 1.3e-10 of the error, axisymmetric stress
/// 7.6e-11 and 3.7e-15 of rho g H; bounds 5e-10 and 3e-10 (4x the largest). The splines'
/// piecewise-quadratic terms are not integrated exactly by the points: a laterally uniform stress
/// leaves lateral nodal forces, and 3D differs from 2D by 9.4e-6 and 1.8e-4 of the error
/// (reported). In axisymmetry the same imbalance next to the axis, where the hoop strain is u_r /
/// r, moved the first column's stress by 1.7 % of rho g H at H/16 and 1.9 % at H/32 (cubic 1.5
/// %, 1.5 %): an error that refinement does not remove, so the reader refuses the splines in
/// axisymmetry.
std::vector<Check> other_geometries(const VerificationContext& ctx,
                                    const std::vector<std::string>& shapes) {
  constexpr double kRatio = 4.0;
  constexpr int kCells = 16;
  std::vector<Check> checks;
  for (const auto& shape : shapes) {
    const bool spline = shape == "bspline2" || shape == "bspline3";
    auto overrides = references::compressed_column_overrides(kCells, kRatio);
    overrides.push_back("solver.shape=" + shape);
    const auto plane_dir = ctx.out_dir / fmt::format("plane_{}", shape);
    run_quiet(read_case_file(ctx.case_file.string(), overrides), plane_dir, ctx.threads);
    const double plane =
        references::compressed_column_errors(ResultsReader(plane_dir / "run.h5"), kRatio).raw;

    auto overrides_3d = overrides;
    const double h = references::kColumnHeight / kCells;
    overrides_3d[1] = fmt::format("grid.extent=[{:.17g}, {:.17g}, {:.17g}]", 4 * h,
                                  references::kColumnHeight + 4 * h, 4 * h);
    overrides_3d[2] = fmt::format("bodies[0].max=[{:.17g}, {:.17g}, {:.17g}]", 4 * h,
                                  references::kColumnHeight, 4 * h);
    const auto dir_3d = ctx.out_dir / fmt::format("3d_{}", shape);
    const auto case_3d = verification_dir() / "column_large_compression_3d.yaml";
    run_quiet(read_case_file(case_3d.string(), overrides_3d), dir_3d, ctx.threads);
    const double error_3d =
        references::compressed_column_errors(ResultsReader(dir_3d / "run.h5"), kRatio).raw;
    const std::string q3 = fmt::format("{}: 3D raw L2 against 2D's, H/16", shape);
    const double d3 = std::abs(error_3d - plane) / plane;
    checks.push_back(spline ? report_only(q3, d3, "lateral quadrature of the splines")
                            : at_most_check(q3, d3, 5e-10,
                                            "the same discrete 1D problem to Newton's "
                                            "tolerance; measured 1.2e-11 to 1.3e-10 (cpdi)"));

    if (shape == "cpdi" || spline)
      continue; // refused in axisymmetry
    checks.push_back(at_most_check(
        fmt::format("{}: axisymmetric stress against plane strain / (rho g H), H/16", shape),
        axisymmetric_difference(ctx, shape, kCells, kRatio), 3e-10,
        "the same discrete 1D problem to Newton's tolerance; measured 4e-15 to 7.6e-11 (gimp)"));
  }
  return checks;
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
        for (const int n : cells) {
          auto overrides = references::compressed_column_overrides(n, ratio);
          overrides.push_back("solver.shape=" + shape);
          const CaseSpec spec = load_verification_case(ctx, overrides);
          const auto dir = ctx.out_dir / fmt::format("ratio{:g}_{}_cells{}", ratio, shape, n);
          run_quiet(spec, dir, ctx.threads);
          const ColumnErrors& e = errors[{ratio, shape, n}] =
              references::compressed_column_errors(ResultsReader(dir / "run.h5"), ratio);
          const std::string at = fmt::format("rho g H/E = {:g}, {}, H/{}", ratio, shape, n);
          // The figure (16 cells, 2 x 2 points per cell) is checked below.
          if (!(ratio == 4.0 && n == 16))
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
            // 1.49 and 1.43, 1.38; the window 0.2 beyond the measured on each side.
            checks.push_back(within_check("raw " + q, raw, 1.2, 1.8,
                                          "domains that follow the stretch keep the order; "
                                          "measured 1.38 to 1.57"));
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
    struct Measured {
      double raw; ///< raw L2 sigma_yy
      double top; ///< top displacement error (uGIMP -0.99 %)
    };
    const std::map<std::string, Measured> measured = {{"cpgimp", {0.0100, -0.0025}},
                                                      {"cpdi", {0.0091, 0.0005}},
                                                      {"bspline2", {0.0135, -0.0041}},
                                                      {"bspline3", {0.00554, -0.0007}}};
    double best = 1.0;
    std::string best_shape;
    for (const auto& [shape, m] : measured) {
      const double value = m.raw;
      const double e = errors[{4.0, shape, 16}].raw;
      checks.push_back(within_check(fmt::format("raw L2 sigma_yy, rho g H/E = 4, {}, H/16", shape),
                                    e, value / 3, 2.5 * value,
                                    fmt::format("measured {:.2f} %; uGIMP 10.5 %", 100 * value)));
      if (e < best) {
        best = e;
        best_shape = shape;
      }
      // Each shape's top displacement within 2.5x its measured magnitude (at least 0.15 %, the
      // scale of cpdi's +0.05 % and bspline3's -0.07 %), of either sign.
      const double top = m.top;
      const double band = std::max(2.5 * std::abs(top), 0.0015);
      checks.push_back(
          within_check(fmt::format("top displacement error, rho g H/E = 4, {}, H/16", shape),
                       errors[{4.0, shape, 16}].top, -band, band,
                       fmt::format("2.5x the measured {:+.2f} %; uGIMP -0.99 %", 100 * top)));
    }
    // The default shape against the target the others meet: a defect, visible as one.
    checks.push_back(known_failure(
        at_most_check("raw L2 sigma_yy, rho g H/E = 4, gimp, H/16", errors[{4.0, "gimp", 16}].raw,
                      0.015, "issue 21's target, which every other shape meets"),
        "uGIMP's fixed domains overlap where the column is squeezed (measured 10.5 %); use "
        "cpgimp, cpdi or a B-spline for large compression"));
    // Implied by the rows above (bspline3's upper bound, 1.39 %, is below it), so reported.
    checks.push_back(
        report_only(fmt::format("best raw L2 sigma_yy at rho g H/E = 4, H/16 ({})", best_shape),
                    best, "issue 21's target 1.5 % (AMPLE: 1.1 %)"));
    for (Check& c : other_geometries(ctx, shapes))
      checks.push_back(std::move(c));
    // cpGIMP's domain is set at the start of a load step and held through it, so the step's
    // consistent tangent needs no derivative of the domain: Newton stays quadratic.
    for (const auto& shape : shapes)
      checks.push_back(
          newton_order_check(fmt::format("Newton's worst order, rho g H/E = 4, {}, H/32", shape),
                             ctx.out_dir / fmt::format("ratio4_{}_cells32", shape) / "newton.log",
                             1.8, "quadratic convergence: the tangent is consistent"));
    return checks;
  };
  return vc;
}

} // namespace talus::verify_cases
