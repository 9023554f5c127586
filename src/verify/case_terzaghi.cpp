// Terzaghi's one-dimensional consolidation (verification/terzaghi.yaml): a column of height H
// drained at its top, loaded by q in a step short enough to be undrained, then held. With
// incompressible constituents the pore water first takes the whole load, p0 = q; then
//   p(y, t) / q = sum_m (2 / M) sin(M (H - y) / H) exp(-M^2 T_v),  M = pi (2 m + 1) / 2,
//   U(T_v) = 1 - sum_m (2 / M^2) exp(-M^2 T_v),                    T_v = c_v t / H^2,
// c_v = k M_c / gamma_w (M_c the constrained modulus). U is measured from the pore pressure,
// 1 - (mean p) / q, and from the settlement, s / s_inf with s_inf = q H / M_c: the first
// guards the flow, the second the coupling (a skeleton that does not feel p settles at once).
// The base pressure is the mean p of the lowest layer of points against the series there.
#include "cases.hpp"

#include <cmath>
#include <fmt/format.h>
#include <stdexcept>

namespace talus::verify_cases {

namespace {

constexpr double kHeight = 1.0, kLoad = 1.0e3, kConstrained = 1.0e7, kLoadTime = 1.0e-6;
constexpr double kPi = 3.14159265358979323846;

/// p / q at height y and time factor T (the series to 1e-15).
double series_pressure(double y, double T) {
  double p = 0;
  for (int m = 0; m < 2000; ++m) {
    const double M = kPi * (2 * m + 1) / 2;
    const double term = 2 / M * std::sin(M * (kHeight - y) / kHeight) * std::exp(-M * M * T);
    p += term;
    if (M * M * T > 40)
      break;
  }
  return p;
}

double series_degree(double T) {
  double u = 1;
  for (int m = 0; m < 2000; ++m) {
    const double M = kPi * (2 * m + 1) / 2;
    u -= 2 / (M * M) * std::exp(-M * M * T);
    if (M * M * T > 40)
      break;
  }
  return u;
}

/// The settlement of height Y (the base's at 0) over its drained value q Y / M_c:
/// (Y - sum_m (2 H / M^2) cos(M (H - Y) / H) exp(-M^2 T_v)) / Y.
double series_settlement(double Y, double T) {
  double s = Y;
  for (int m = 0; m < 2000; ++m) {
    const double M = kPi * (2 * m + 1) / 2;
    s -= 2 * kHeight / (M * M) * std::cos(M * (kHeight - Y) / kHeight) * std::exp(-M * M * T);
    if (M * M * T > 40)
      break;
  }
  return s / Y;
}

struct Measured {
  double degree_from_pressure = 0;
  double settlement = 0, settlement_exact = 0; ///< the top points' over q Y / M_c
  double base_pressure = 0, base_exact = 0;    ///< / q, the lowest layer of points
  double profile_error = 0;                    ///< volume-weighted L2 of p / q
  double interior_error = 0;                   ///< largest |p / q - exact| below the top 4 cells
};

/// The column at the frame nearest to time factor T of the consolidation stage (T < 0: the
/// load step's end); h the cell size.
Measured measure(const ResultsReader& results, double T, double h) {
  Index frame = 0;
  double best = 1e300;
  const double target = T < 0 ? kLoadTime : kLoadTime + T;
  for (Index f = 0; f < results.frame_count(); ++f)
    if (const double d = std::abs(results.frame_time(f) - target); d < best) {
      best = d;
      frame = f;
    }
  // A run that did not write the frame asked for fails the row instead of measuring another.
  if (!(best <= 1e-9 * std::max(1.0, target)))
    throw std::runtime_error(fmt::format("terzaghi: no frame at t = {:g}", target));
  const auto [x0, x, volume, p, d] = read_pore_frame(results, frame);
  const double Tv = std::max(T, 0.0);
  double V = 0, pV = 0, err = 0, norm = 0, interior = 0, top_settlement = 0, top_exact = 0,
         top_count = 0, base = 0, base_exact = 0, base_count = 0;
  for (std::size_t s = 0; s < p.size(); ++s) {
    const double Y = x0[d * s + 1];
    const double exact = T < 0 ? 1.0 : series_pressure(Y, Tv);
    V += volume[s];
    pV += volume[s] * p[s];
    err += volume[s] * std::pow(p[s] / kLoad - exact, 2);
    if (Y < kHeight - 4 * h)
      interior = std::max(interior, std::abs(p[s] / kLoad - exact));
    norm += volume[s];
    if (Y > kHeight - h / 2) {
      top_settlement += (Y - x[d * s + 1]) / (kLoad * Y / kConstrained);
      top_exact += T < 0 ? 0.0 : series_settlement(Y, Tv);
      ++top_count;
    }
    if (Y < h / 2) {
      base += p[s] / kLoad;
      base_exact += exact;
      ++base_count;
    }
  }
  Measured m;
  m.degree_from_pressure = 1 - pV / V / kLoad;
  m.settlement = top_settlement / top_count;
  m.settlement_exact = top_exact / top_count;
  m.base_pressure = base / base_count;
  m.base_exact = base_exact / base_count;
  m.profile_error = std::sqrt(err / norm);
  m.interior_error = interior;
  return m;
}

/// The run of the case file at cell size H / n and consolidation step dt into dir: to T_v = 1
/// with a frame every 0.05, or with `until` > 0 to T_v = until with frames at the stages' ends;
/// or with `drained_dt` > 0 one stage instead, the load put on in one step that long.
struct ColumnRun {
  int n = 16;
  double dt = 0.01, until = 0, drained_dt = 0;
  std::string shape = {};        ///< solver.shape, if not the case's (linear)
  bool top_on_grid_face = false; ///< the grid ends at the top, a drained face
};
ResultsReader run_column(const VerificationContext& ctx, const std::string& file,
                         const ColumnRun& run, const std::filesystem::path& dir) {
  const int n = run.n;
  const double dt = run.dt, drained_dt = run.drained_dt;
  const double h = kHeight / n;
  VerificationContext c = ctx;
  c.case_file = verification_dir() / file;
  const bool solid = file.find("3d") != std::string::npos;
  const std::string z = solid ? fmt::format(", {:.17g}", 2 * h) : "";
  std::vector<std::string> overrides = {
      fmt::format("grid.cell_size={:.17g}", h),
      fmt::format("grid.extent=[{:.17g}, {:.17g}{}]", 2 * h, kHeight + 4 * h, z),
      fmt::format("bodies[0].max=[{:.17g}, {:.17g}{}]", 2 * h, kHeight, z),
      fmt::format("stages[1].time.dt={:.17g}", dt)};
  if (!run.shape.empty())
    overrides.push_back("solver.shape=" + run.shape);
  if (run.top_on_grid_face) {
    overrides[1] = fmt::format("grid.extent=[{:.17g}, {:.17g}{}]", 2 * h, kHeight, z);
    overrides.emplace_back("water={unit_weight: 1.0e4, drained: [y_max]}");
  }
  if (run.until == 0)
    overrides.emplace_back("output.every_time=0.05"); // every T_v measured, and the stage ends
  if (run.until > 0) {
    overrides.push_back(fmt::format("stages[1].time.end_time={:.17g}", run.until));
    overrides.emplace_back("output.every_steps=1000000");
  }
  if (drained_dt > 0)
    overrides = {overrides[0], overrides[1], overrides[2],
                 fmt::format("stages=[{{name: load, analysis: implicit_quasistatic, time: "
                             "{{end_time: {0:.17g}, dt: {0:.17g}}}}}]",
                             drained_dt)};
  run_quiet(load_verification_case(c, overrides), dir, ctx.threads);
  return ResultsReader(dir / "run.h5");
}

} // namespace

VerificationCase terzaghi() {
  VerificationCase vc;
  vc.name = "terzaghi";
  vc.description = "Terzaghi's 1D consolidation (implicit u-p, backward Euler, pressure "
                   "projection): the undrained start, the degree of consolidation and the base "
                   "pressure against the series, observed orders in space and time, an endless "
                   "step against the drained settlement, 3D and axisymmetry against plane strain.";
  vc.tiers = {"fast", "full"};
  vc.run = [](const VerificationContext& ctx) {
    std::vector<Check> checks;
    // The time factors the issue names; H/32 with steps of 0.001, whose error in U is a third
    // of space's at T_v = 0.1 (0.00036 of 0.0011, from the time study below).
    const std::vector<double> factors = {0.05, 0.1, 0.2, 0.5, 1.0};
    const double h = kHeight / 32;
    const ResultsReader fine =
        run_column(ctx, "terzaghi.yaml", {32, 1e-3}, ctx.out_dir / "cells32");
    const Measured start = measure(fine, -1, h);
    // The undrained start loses the water of the drained top cell's points (the series' layer,
    // sqrt(c_v t) = 1 mm, is far inside it): measured h / (4H), halving with h.
    checks.push_back(within_check("undrained start: mean p / q, H/32",
                                  1 - start.degree_from_pressure, 1 - h / (2 * kHeight), 1 + 1e-9,
                                  "p0 = q with incompressible constituents; the top "
                                  "cell's share lost, 2x the measured h / (4H)"));
    checks.push_back(report_only("undrained start: L2 of p / q - 1, H/32", start.profile_error,
                                 "the top cells' overshoot (docs/case-format.md, "
                                 "consolidation_step)"));
    checks.push_back(at_most_check(
        "undrained start: largest |p / q - 1| below the top four cells, H/32", start.interior_error,
        0.03, "3x the measured; without the pressure projection the column checkerboards (0.3)"));
    for (const double T : factors) {
      const Measured m = measure(fine, T, h);
      const double U = series_degree(T);
      checks.push_back(absolute_check(
          fmt::format("U(T_v = {}) from the pore pressure, H/32", T), m.degree_from_pressure, U,
          0.003, "1 - mean p / q against the series; 3.5x the largest error (0.0008 at 0.05)"));
      checks.push_back(absolute_check(
          fmt::format("base p / q at T_v = {}, H/32", T), m.base_pressure, m.base_exact, 0.002,
          "the lowest layer of points against the series there; 2.5x the largest (0.0008)"));
      checks.push_back(absolute_check(
          fmt::format("top settlement / (q Y / M) at T_v = {}, H/32", T), m.settlement,
          m.settlement_exact, 0.0015,
          "the top points' against the series' at their Y; 2.5x the largest (0.0006): the "
          "skeleton follows the water out"));
    }
    // The other shape functions on the same column: U at every T_v within the linear bound.
    for (const std::string shape : {"gimp", "bspline2", "cpdi"}) {
      ColumnRun run{32, 1e-3};
      run.shape = shape;
      const ResultsReader r = run_column(ctx, "terzaghi.yaml", run, ctx.out_dir / shape);
      double worst = 0;
      for (const double T : factors)
        worst = std::max(worst, std::abs(measure(r, T, h).degree_from_pressure - series_degree(T)));
      Check c = at_most_check("largest |U - series| over the T_v, H/32, " + shape, worst, 0.003,
                              "linear's bound");
      if (shape == "bspline2")
        c = known_failure(std::move(c),
                          "quadratic B-splines drain too slowly in consolidation "
                          "(0.011 at H/32): held surface nodes leave p = p_below / 8 at the "
                          "surface (the splines do not interpolate); with the surface "
                          "on a drained grid face U(0.1) is off by 0.0019 at H/16, "
                          "linear's 0.0016");
      checks.push_back(std::move(c));
    }
    // The quadratic B-splines with the drained top on a grid face, where they are clamped.
    {
      ColumnRun run{32, 1e-3};
      run.shape = "bspline2";
      run.top_on_grid_face = true;
      const ResultsReader r = run_column(ctx, "terzaghi.yaml", run, ctx.out_dir / "bspline2_face");
      double worst = 0;
      for (const double T : factors)
        worst = std::max(worst, std::abs(measure(r, T, h).degree_from_pressure - series_degree(T)));
      checks.push_back(at_most_check(
          "largest |U - series| over the T_v, H/32, bspline2 drained through a grid face", worst,
          0.003,
          "linear's bound, 3.5x the measured 0.0008: the known failure above is the "
          "free surface inside the grid"));
    }
    // Space: the L2 error of p at T_v = 0.1 on H/8, H/16, H/32 with steps of 1e-4 (time's
    // error a tenth of space's at H/32).
    std::vector<double> space_error;
    for (const int n : {8, 16, 32}) {
      const ResultsReader r =
          run_column(ctx, "terzaghi.yaml", {n, 1e-4, 0.1}, ctx.out_dir / fmt::format("space{}", n));
      space_error.push_back(measure(r, 0.1, kHeight / n).profile_error);
      checks.push_back(report_only(fmt::format("L2 of p / q at T_v = 0.1, H/{}, dt = 1e-4", n),
                                   space_error.back()));
    }
    for (std::size_t i = 1; i < space_error.size(); ++i)
      checks.push_back(within_check(
          fmt::format("observed order in space, H/{} to H/{}", 4 << i, 8 << i),
          observed_order(space_error[i - 1], space_error[i]), 0.9, 2.3,
          "between the undrained start's first order (the lost top cell) and linear elements' "
          "second (measured 1.83, 1.43)"));
    // Time: U(0.1) on H/32 at dt = 0.02, 0.01, 0.005; the differences of successive runs take
    // the (fixed) space error out.
    std::vector<double> degree;
    for (const double dt : {0.02, 0.01, 0.005}) {
      const ResultsReader r =
          run_column(ctx, "terzaghi.yaml", {32, dt, 0.1}, ctx.out_dir / fmt::format("dt{}", dt));
      degree.push_back(measure(r, 0.1, h).degree_from_pressure);
      checks.push_back(report_only(fmt::format("U(0.1) - series, H/32, dt = {}", dt),
                                   degree.back() - series_degree(0.1)));
    }
    checks.push_back(within_check(
        "observed order in time (successive differences of U(0.1))",
        observed_order(std::abs(degree[0] - degree[1]), std::abs(degree[1] - degree[2])), 0.8, 1.2,
        "backward Euler: 1 (measured 1.05)"));
    // An endless step is the drained answer: the load on the skeleton, no pressure left.
    {
      const ResultsReader r =
          run_column(ctx, "terzaghi.yaml", {16, 1, 0, 1e6}, ctx.out_dir / "drained");
      const Measured m = measure(r, 1e6 - kLoadTime, kHeight / 16);
      checks.push_back(at_most_check("step of 1e6 s: |mean p| / q",
                                     std::abs(1 - m.degree_from_pressure), 1e-5,
                                     "what a step that long leaves: eps gamma_w H^2 / (k dt) = "
                                     "1e-6 q (measured 3.3e-7)"));
      checks.push_back(absolute_check("step of 1e6 s: top settlement / (q Y / M)", m.settlement,
                                      1.0, 1e-6, "the drained column (measured 3.4e-7)"));
    }
    // 3D and axisymmetry: the same discrete 1D problem as plane strain.
    {
      const ResultsReader plane =
          run_column(ctx, "terzaghi.yaml", {16, 0.01}, ctx.out_dir / "plane16");
      const ResultsReader solid =
          run_column(ctx, "terzaghi_3d.yaml", {16, 0.01}, ctx.out_dir / "solid16");
      const ResultsReader axi =
          run_column(ctx, "terzaghi_axisymmetric.yaml", {16, 0.01}, ctx.out_dir / "axi16");
      double solid_diff = 0, axi_diff = 0;
      for (const double T : factors) {
        const double u = measure(plane, T, kHeight / 16).degree_from_pressure;
        solid_diff = std::max(solid_diff,
                              std::abs(measure(solid, T, kHeight / 16).degree_from_pressure - u));
        axi_diff =
            std::max(axi_diff, std::abs(measure(axi, T, kHeight / 16).degree_from_pressure - u));
      }
      checks.push_back(at_most_check("3D U less plane strain's, largest over the T_v", solid_diff,
                                     1e-7, "Newton's tolerance over 100 steps (6e-13)"));
      checks.push_back(at_most_check("axisymmetric U less plane strain's, largest over the T_v",
                                     axi_diff, 1e-7, "Newton's tolerance over 100 steps (9e-12)"));
    }
    return checks;
  };
  return vc;
}

} // namespace talus::verify_cases
