// The elastic self-weight column below a water table at its top (verification/
// submerged_column.yaml): pore pressure u = gamma_w (H - y) on the points, the material on the
// effective stress. Equilibrium holds the total stress, -rho_sat g (H - Y); the effective stress
// sigma_yy + u is then -(rho_sat g - gamma_w) (H - Y), and the skeleton settles under that
// buoyant weight only, v(Y) = -(rho_sat g - gamma_w) (H Y - Y^2 / 2) / M. A dry column of the
// same weight settles (rho_sat g) / (rho_sat g - gamma_w) = 2 times as much, and its effective
// stress is the total one: both measures are 50 % and more wrong without the water. The
// measures are the volume-weighted relative L2 errors of the raw point sigma'_yy and of v at
// H/8, H/16 and H/32 with GIMP; the stress converges at first order as in the dry column.
// Measured: sigma'_yy 5.4 %, 2.7 %, 1.34 % (orders 1.003, 1.006; the dry column's figures),
// settlement 0.37 %, 0.073 %, 0.010 % (orders 2.4 and 2.8). Checks: the stress orders in
// [0.8, 1.2], the stress error at H/32 at most 3 % (2.2x) and the settlement error at most
// 0.03 % (2.9x). The stress guards the saturated weight and the balance (sigma_yy + u is right
// for any total stress that balances it); the settlement guards the water's force in the
// balance: without it the column settles as a dry one of the same weight, 100 % more (the
// formula; the same break fails slope_drawdown). A ponded run (free water H/4 deep) must give
// the same effective stress and settlement to round-off.
#include "cases.hpp"

#include <cmath>
#include <fmt/format.h>

namespace talus::verify_cases {

namespace {

constexpr double kHeight = 1.0, kWidth = 0.25, kSaturatedDensity = 2000.0, kGravity = 10.0,
                 kWaterWeight = 1.0e4, kYoung = 1.0e7, kPoisson = 0.3;

struct ColumnErrors {
  double effective_stress = 0, settlement = 0;
};

/// The errors of a run whose water table stands at `level` (at or above the top).
ColumnErrors column_errors(const ResultsReader& results, double level) {
  Index rows = 0, dims = 0, cols = 0;
  const auto x0 = results.read(0, "position", &rows, &dims);
  const Index last = results.frame_count() - 1;
  const auto x = results.read(last, "position", &rows, &dims);
  const auto volume = results.read(0, "volume", &rows, &cols);
  const auto stress = results.read(last, "stress", &rows, &cols);
  const double buoyant = kSaturatedDensity * kGravity - kWaterWeight;
  const double constrained = kYoung * (1 - kPoisson) / ((1 + kPoisson) * (1 - 2 * kPoisson)); // M
  double stress_error = 0, stress_norm = 0, v_error = 0, v_norm = 0;
  for (Index p = 0; p < rows; ++p) {
    const auto s = static_cast<std::size_t>(p);
    const auto d = static_cast<std::size_t>(dims);
    const double Y = x0[d * s + 1], y = x[d * s + 1];
    const double u = kWaterWeight * std::max(0.0, level - y);
    const double effective = stress[s * static_cast<std::size_t>(cols) + 3] + u; // xx, xy, xz, yy
    const double exact_stress = -buoyant * (kHeight - Y);
    stress_error += volume[s] * (effective - exact_stress) * (effective - exact_stress);
    stress_norm += volume[s] * exact_stress * exact_stress;
    const double exact_v = -buoyant * (kHeight * Y - 0.5 * Y * Y) / constrained;
    v_error += volume[s] * (y - Y - exact_v) * (y - Y - exact_v);
    v_norm += volume[s] * exact_v * exact_v;
  }
  return {std::sqrt(stress_error / stress_norm), std::sqrt(v_error / v_norm)};
}

} // namespace

VerificationCase submerged_column() {
  VerificationCase vc;
  vc.name = "submerged_column";
  vc.distributable = true;
  vc.description = "Elastic column below a water table (implicit quasi-static, GIMP): effective "
                   "sigma_yy against -(rho_sat g - gamma_w)(H - Y) and the settlement under the "
                   "buoyant weight, relative L2 errors under refinement.";
  vc.tiers = {"fast", "full"};
  vc.run = [](const VerificationContext& ctx) {
    std::vector<Check> checks;
    const std::vector<int> cells = {8, 16, 32};
    std::vector<ColumnErrors> errors;
    for (const int n : cells) {
      const double h = kHeight / n;
      const CaseSpec spec = load_verification_case(
          ctx, {fmt::format("grid.cell_size={:.17g}", h),
                fmt::format("grid.extent=[{:.17g}, {:.17g}]", kWidth, kHeight + 4 * h)});
      const auto dir = ctx.out_dir / fmt::format("cells{}", n);
      run_quiet(spec, dir, ctx.threads);
      errors.push_back(column_errors(ResultsReader(dir / "run.h5"), kHeight));
      const std::string stress = fmt::format("L2 error effective sigma_yy, H/{}", n);
      const std::string settlement = fmt::format("L2 error settlement, H/{}", n);
      const bool finest = n == cells.back();
      checks.push_back(finest ? at_most_check(stress, errors.back().effective_stress, 0.03,
                                              "volume-weighted, relative; 2.2x the measured")
                              : report_only(stress, errors.back().effective_stress,
                                            "volume-weighted, relative"));
      checks.push_back(
          finest ? at_most_check(settlement, errors.back().settlement, 3e-4,
                                 "volume-weighted, relative; 2.9x the measured; a "
                                 "dry column settles twice as much")
                 : report_only(settlement, errors.back().settlement, "volume-weighted, relative"));
    }
    // Ponded: free water a quarter of the height deep on the finest column. Its weight rests on
    // the skeleton and on the pore water alike, so the effective stress and the settlement are
    // the column's without it (Terzaghi), to round-off: the same balance, the same weights.
    const int n = cells.back();
    const double h = kHeight / n;
    const auto ponded_dir = ctx.out_dir / fmt::format("cells{}_ponded", n);
    run_quiet(load_verification_case(
                  ctx, {fmt::format("grid.cell_size={:.17g}", h),
                        fmt::format("grid.extent=[{:.17g}, {:.17g}]", kWidth, kHeight + 4 * h),
                        fmt::format("water.level={:.17g}", 1.25 * kHeight)}),
              ponded_dir, ctx.threads);
    const ColumnErrors ponded = column_errors(ResultsReader(ponded_dir / "run.h5"), 1.25 * kHeight);
    checks.push_back(at_most_check(
        fmt::format("ponded H/4 deep: effective sigma_yy error less the unponded, H/{}", n),
        std::abs(ponded.effective_stress - errors.back().effective_stress), 1e-9,
        "round-off: the effective stress is sigma_yy + u of the same skeleton"));
    checks.push_back(
        at_most_check(fmt::format("ponded H/4 deep: settlement error less the unponded, H/{}", n),
                      std::abs(ponded.settlement - errors.back().settlement), 1e-9,
                      "round-off; the water's pressure on the top missing, the top would lift"));
    for (std::size_t i = 1; i < errors.size(); ++i)
      checks.push_back(within_check(
          fmt::format("observed order, effective stress, H/{} to H/{}", cells[i - 1], cells[i]),
          observed_order(errors[i - 1].effective_stress, errors[i].effective_stress), 0.8, 1.2,
          "theory 1 (raw point stress)"));
    return checks;
  };
  return vc;
}

} // namespace talus::verify_cases
