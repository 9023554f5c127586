// Mandel's problem (verification/mandel.yaml): a specimen 2a wide between rigid, frictionless,
// impermeable platens, drained at its sides, squeezed at t = 0 by a force 2F (F = sigma a per
// half) that is then held. Cheng & Detournay (1988) give, with c the consolidation coefficient,
// B Skempton's coefficient, nu and nu_u the drained and undrained Poisson's ratios and a_n the
// roots of tan a_n = (1 - nu) / (nu_u - nu) a_n,
//   p(x, t) = 2 p0 sum_n sin a_n / (a_n - sin a_n cos a_n) (cos(a_n x / a) - cos a_n)
//             exp(-a_n^2 c t / a^2),                         p0 = F B (1 + nu_u) / (3 a),
//   eps_yy(t) = -F (1 - nu) / (2 G a)
//               + F (1 - nu_u) / (G a) sum_n sin a_n cos a_n / (a_n - sin a_n cos a_n) exp(...).
// The platen keeps the specimen's height uniform, so as the sides drain and soften the load
// moves to the stiffer undrained middle: the centre's pressure first rises (the Mandel-Cryer
// effect, 1.0547 p0 at c t / a^2 = 0.058 for this set), which an uncoupled diffusion or a
// flexible load (a traction without the platen) cannot do.
#include "cases.hpp"
#include "histories.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <fmt/format.h>
#include <stdexcept>
#include <string>
#include <vector>

namespace talus::verify_cases {

namespace {

constexpr double kWidth = 1.0 /* a */, kHeight = 0.25 /* b */, kLoad = 1.0e3 /* sigma */;
constexpr double kShear = 0.75e6, kBulk = 1.0e6, kBiot = 0.6, kBiotModulus = 4.705882352941176e6,
                 kMobility = 1.5e-6, kLoadTime = 1.0e-6;
constexpr double kPi = 3.14159265358979323846;

/// The poroelastic constants of the set and the series' roots.
struct MandelSeries {
  double nu = 0, nu_u = 0, skempton = 0, c = 0;
  std::vector<double> roots;

  MandelSeries() {
    nu = (3 * kBulk - 2 * kShear) / (6 * kBulk + 2 * kShear);
    const double undrained = kBulk + kBiot * kBiot * kBiotModulus;
    nu_u = (3 * undrained - 2 * kShear) / (6 * undrained + 2 * kShear);
    skempton = kBiot * kBiotModulus / undrained;
    c = kMobility * kBiotModulus * (kBulk + 4 * kShear / 3) / (undrained + 4 * kShear / 3);
    const double slope = (1 - nu) / (nu_u - nu);
    // One root in each (n pi, n pi + pi / 2) (in (0, pi / 2) for n = 0, slope > 1): bisection.
    for (int n = 0; n < 4000; ++n) {
      double lo = n * kPi + 1e-12, hi = n * kPi + kPi / 2 - 1e-12;
      for (int k = 0; k < 200 && hi - lo > 1e-15 * hi; ++k) {
        const double mid = (lo + hi) / 2;
        (std::tan(mid) - slope * mid < 0 ? lo : hi) = mid;
      }
      roots.push_back((lo + hi) / 2);
    }
  }
  double p0() const { return kLoad * kWidth * skempton * (1 + nu_u) / (3 * kWidth); }
  double time_factor(double t) const { return c * t / (kWidth * kWidth); }

  /// p(x, t) / p0.
  double pressure(double x, double t) const {
    const double T = time_factor(t);
    double sum = 0;
    for (const double a : roots) {
      if (a * a * T > 40)
        break;
      sum += std::sin(a) / (a - std::sin(a) * std::cos(a)) *
             (std::cos(a * x / kWidth) - std::cos(a)) * std::exp(-a * a * T);
    }
    return 2 * sum;
  }
  /// eps_yy(t), the platen's strain of the specimen's height.
  double strain(double t) const {
    const double T = time_factor(t), F = kLoad * kWidth;
    double sum = 0;
    for (const double a : roots) {
      if (a * a * T > 40)
        break;
      sum += std::sin(a) * std::cos(a) / (a - std::sin(a) * std::cos(a)) * std::exp(-a * a * T);
    }
    return -F * (1 - nu) / (2 * kShear * kWidth) + F * (1 - nu_u) / (kShear * kWidth) * sum;
  }
};

const MandelSeries& series() {
  static const MandelSeries s;
  return s;
}

/// One frame of the specimen against the series.
struct Frame {
  double t = 0;
  double profile_error = 0;            ///< volume-weighted L2 of (p - series) / p0
  double centre = 0, centre_exact = 0; ///< the points of the first column: mean p / p0
  double strain = 0;                   ///< the top row's mean (y - Y) / Y
  std::vector<double> x, p;            ///< per column of points: mean X / a, p / p0
};

Frame measure(const ResultsReader& results, Index frame, double h) {
  const auto [x0, x, volume, p, d] = read_pore_frame(results, frame);
  const MandelSeries& s = series();
  Frame f;
  f.t = results.frame_time(frame);
  const int columns = static_cast<int>(std::lround(2 * kWidth / h));
  std::vector<double> column_x(at(columns), 0.0), column_p(at(columns), 0.0),
      column_n(at(columns), 0.0);
  double V = 0, err = 0, centre_n = 0, top_n = 0;
  for (std::size_t k = 0; k < p.size(); ++k) {
    const double X = x0[d * k], Y = x0[d * k + 1];
    const double pk = p[k] / s.p0(), exact = s.pressure(X, f.t);
    V += volume[k];
    err += volume[k] * (pk - exact) * (pk - exact);
    const int column = std::clamp(static_cast<int>(X / kWidth * columns), 0, columns - 1);
    column_x[at(column)] += X;
    column_p[at(column)] += pk;
    column_n[at(column)] += 1;
    if (X < h / 2) {
      f.centre += pk;
      f.centre_exact += exact;
      ++centre_n;
    }
    if (Y > kHeight - h / 2) {
      f.strain += (x[d * k + 1] - Y) / Y;
      ++top_n;
    }
  }
  // A run that measured nothing fails the row instead of passing it.
  if (!(V > 0 && centre_n > 0 && top_n > 0))
    throw std::runtime_error("mandel: no points in the frame's centre column or top row");
  f.profile_error = std::sqrt(err / V);
  f.centre /= centre_n;
  f.centre_exact /= centre_n;
  f.strain /= top_n;
  for (int c = 0; c < columns; ++c)
    if (column_n[at(c)] > 0) {
      f.x.push_back(column_x[at(c)] / column_n[at(c)] / kWidth);
      f.p.push_back(column_p[at(c)] / column_n[at(c)]);
    }
  return f;
}

/// The frame at c t / a^2 = T after the load step (T = 0: its end); a run that did not write
/// it fails the row.
Index frame_at(const ResultsReader& results, double T) {
  const auto distance = [&](Index f) {
    return std::abs(series().time_factor(results.frame_time(f) - kLoadTime) - T);
  };
  Index best = 0;
  for (Index f = 1; f < results.frame_count(); ++f)
    if (distance(f) < distance(best))
      best = f;
  if (distance(best) > 1e-9 * std::max(T, 1.0))
    throw std::runtime_error(fmt::format("mandel: no frame at c t / a^2 = {:g}", T));
  return best;
}

/// The centre column's largest p / p0 over the frames after the load step, the frame's time
/// and the series' largest at the same points; its history goes into `plot`.
struct Peak {
  double measured = 0, t = 0, exact = 0;
};
Peak centre_peak(const ResultsReader& r, double h, const std::string& series_name,
                 HistoryPlot& plot) {
  Peak peak;
  History history{"centre p / p0", series_name, {}, {}};
  for (Index k = frame_at(r, 0); k < r.frame_count(); ++k) {
    const Frame f = measure(r, k, h);
    history.x.push_back(series().time_factor(f.t));
    history.y.push_back(f.centre);
    if (f.centre > peak.measured)
      peak = {f.centre, f.t, peak.exact};
    peak.exact = std::max(peak.exact, f.centre_exact);
  }
  plot.add(std::move(history));
  return peak;
}

/// The specimen at cell size a / n into dir: the case's stages, or with `step` > 0 one stage to
/// c t / a^2 = 0.1 in steps of `step` (in c t / a^2); `platen` false: a flexible load instead.
struct SpecimenRun {
  int n = 16;
  double step = 0;
  bool platen = true;
};
ResultsReader run_specimen(const VerificationContext& ctx, const SpecimenRun& run,
                           const std::filesystem::path& dir) {
  std::vector<std::string> overrides = {fmt::format("grid.cell_size={:.17g}", kWidth / run.n)};
  if (!run.platen)
    overrides.emplace_back("boundaries={x_min: roller, y_min: roller}");
  const auto seconds = [](double T) { return T * kWidth * kWidth / series().c; };
  if (run.step > 0)
    overrides.push_back(fmt::format(
        "stages=[{{name: load, analysis: implicit_quasistatic, time: {{end_time: {0:.17g}, dt: "
        "{0:.17g}}}}}, {{name: consolidate, analysis: implicit_quasistatic, time: {{end_time: "
        "{1:.17g}, dt: {2:.17g}}}}}]",
        kLoadTime, seconds(0.1), seconds(run.step)));
  run_quiet(load_verification_case(ctx, overrides), dir, ctx.threads);
  return ResultsReader(dir / "run.h5");
}

/// The error in space: the centre's p at c t / a^2 = 0.1 against the series at the same points,
/// with the case's steps (0.002) on each grid; successive differences of the error take the
/// time error, the same on every grid, out (steps far shorter than h^2 / (6 c) would instead
/// make the drained side oscillate: the consolidation_step warning).
void space_study(const VerificationContext& ctx, const std::vector<int>& grids,
                 std::vector<Check>& checks) {
  std::vector<double> error;
  for (const int n : grids) {
    const ResultsReader r = run_specimen(ctx, {n, 0.002}, ctx.out_dir / fmt::format("space{}", n));
    const Frame f = measure(r, frame_at(r, 0.1), kWidth / n);
    error.push_back(f.centre - f.centre_exact);
    checks.push_back(report_only(
        fmt::format("centre p / p0 - series at c t / a^2 = 0.1, a/{}, steps of 0.002", n),
        error.back()));
  }
  for (std::size_t i = 2; i < error.size(); ++i)
    checks.push_back(within_check(
        fmt::format("observed order in space (successive differences of the centre's error), "
                    "a/{} to a/{}",
                    grids[i - 2], grids[i]),
        observed_order(std::abs(error[i - 2] - error[i - 1]), std::abs(error[i - 1] - error[i])),
        1.6, 2.4, "linear elements: 2 (measured 1.99, 2.01)"));
}

/// The error in time: the centre's p at c t / a^2 = 0.1 on a/16 with steps of 0.004, 0.002,
/// 0.001; successive differences take the (fixed) error in space out.
void time_study(const VerificationContext& ctx, std::vector<Check>& checks) {
  std::vector<double> centre;
  for (const double step : {0.004, 0.002, 0.001}) {
    const ResultsReader r =
        run_specimen(ctx, {16, step}, ctx.out_dir / fmt::format("step{}", step));
    const Frame f = measure(r, frame_at(r, 0.1), kWidth / 16);
    centre.push_back(f.centre);
    checks.push_back(report_only(
        fmt::format("centre p / p0 - series at c t / a^2 = 0.1, a/16, steps of {}", step),
        f.centre - f.centre_exact));
  }
  checks.push_back(
      within_check("observed order in time (successive differences of the centre's p at 0.1)",
                   observed_order(std::abs(centre[0] - centre[1]), std::abs(centre[1] - centre[2])),
                   0.8, 1.2, "backward Euler: 1 (measured 0.96)"));
}

} // namespace

VerificationCase mandel() {
  VerificationCase vc;
  vc.name = "mandel";
  vc.description = "Mandel's problem (implicit u-p under a rigid platen, compressible "
                   "constituents: Biot alpha = 0.6, M = 4.7 G): the undrained start, p(x, t) and "
                   "the platen's settlement against Cheng & Detournay's series, observed orders "
                   "in space and time, and the Mandel-Cryer overshoot at the centre, which a "
                   "flexible load lacks.";
  vc.tiers = {"fast", "full"};
  vc.run = [](const VerificationContext& ctx) {
    std::vector<Check> checks;
    const MandelSeries& s = series();
    const std::vector<int> divisions =
        ctx.tier == "full" ? std::vector<int>{8, 16, 32} : std::vector<int>{8, 16};
    const int n = divisions.back();
    const bool full = n == 32;
    const double h = kWidth / n;
    HistoryPlot profiles({}, "x / a"), centre({}, "c t / a^2");
    const ResultsReader r = run_specimen(ctx, {n}, ctx.out_dir / fmt::format("a{}", n));
    // The undrained start: p0 = F B (1 + nu_u) / (3 a) in the middle; first order in h.
    checks.push_back(absolute_check(fmt::format("undrained start: centre p / p0, a/{}", n),
                                    measure(r, frame_at(r, 0), h).centre, 1.0, full ? 0.005 : 0.01,
                                    "2.5x the measured (0.004 at a/16, 0.002 at a/32); the "
                                    "compressible constituents' B and nu_u set p0"));
    // Bounds 2.5x the measured at a/16 and a/32 (0.020, 0.012; 0.0025, 0.0023; 0.0034, 0.0034:
    // the later times' error is the steps', 0.002 then 0.01 in c t / a^2).
    const std::vector<std::array<double, 3>> bounds = {
        {0.01, 0.05, 0.03}, {0.1, 0.0065, 0.006}, {0.5, 0.0085, 0.0085}};
    for (const auto& [T, fast_bound, full_bound] : bounds) {
      const Frame f = measure(r, frame_at(r, T), h);
      checks.push_back(
          at_most_check(fmt::format("L2 of (p - series) / p0 at c t / a^2 = {}, a/{}", T, n),
                        f.profile_error, full ? full_bound : fast_bound, "2.5x the measured"));
      checks.push_back(
          relative_check(fmt::format("platen strain eps_yy at c t / a^2 = {}, a/{}", T, n),
                         f.strain, s.strain(f.t), 0.004,
                         "the top row's (y - Y) / Y against the series; 3x the largest (0.0014)"));
      History exact{"p / p0", fmt::format("series, {}", T), {}, {}};
      for (int k = 0; k <= 50; ++k) {
        exact.x.push_back(k / 50.0);
        exact.y.push_back(s.pressure(k / 50.0 * kWidth, f.t));
      }
      profiles.add({"p / p0", fmt::format("c t / a^2 = {}, a/{}", T, n), f.x, f.p});
      profiles.add(std::move(exact));
    }
    const Peak peak = centre_peak(r, h, fmt::format("a/{}", n), centre);
    checks.push_back(absolute_check(
        fmt::format("centre peak p / p0 (Mandel-Cryer), a/{}", n), peak.measured, peak.exact, 0.005,
        "the series' largest at the same points and frames (1.0547 at x = 0)"));
    checks.push_back(absolute_check(fmt::format("time of the centre peak, c t / a^2, a/{}", n),
                                    s.time_factor(peak.t), 0.058, 0.006,
                                    "the series' 0.058; three steps of 0.002"));
    // A flexible load of the same size: the same start, no overshoot.
    const ResultsReader flexible_run =
        run_specimen(ctx, {16, 0, false}, ctx.out_dir / "flexible16");
    const Peak flexible = centre_peak(flexible_run, kWidth / 16, "flexible load, a/16", centre);
    checks.push_back(within_check("flexible load (no platen): centre peak p / p0, a/16",
                                  flexible.measured, 0.99, 1.01,
                                  "its start (1.004 measured): the load stays uniform, so "
                                  "nothing moves to the middle; the platen's peak is 1.053"));
    History exact{"centre p / p0", "series at x = 0", {}, {}};
    for (int k = 0; k <= 200; ++k) {
      exact.x.push_back(0.5 * k / 200);
      exact.y.push_back(s.pressure(0, 0.5 * k / 200 / s.c * kWidth * kWidth));
    }
    centre.add(std::move(exact));
    profiles.write(ctx.out_dir, "mandel_profiles",
                   "Mandel's problem: pore pressure across the specimen (column means)");
    centre.write(ctx.out_dir, "mandel_centre",
                 "Mandel's problem: the centre's pore pressure (the Mandel-Cryer effect)");
    space_study(ctx, full ? std::vector<int>{8, 16, 32, 64} : std::vector<int>{8, 16, 32}, checks);
    time_study(ctx, checks);
    return checks;
  };
  return vc;
}

} // namespace talus::verify_cases
