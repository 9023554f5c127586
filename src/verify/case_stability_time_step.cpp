// Time-step stability of both solvers on the vibrating bar (verification/vibrating_bar.yaml,
// 32 cells, E = 100 Pa, rho = 1, c = 10 m/s: a conservative scene, no damping, no contact).
//  * Explicit (MUSL, FLIP, GIMP): CFL 0.1 to 0.95 over ten periods. The leapfrog is stable up
//    to Courant 1 for the linear bar and conserves a modified energy, so no energy may appear:
//    the mean energy over the last period may exceed the mean over the first by no more than
//    the sampling error of a period mean, twice (w dt / 2)(dt / T) (the staggering oscillation
//    below, averaged over a period of rows that does not close exactly). What may go is bounded
//    too: the transfers lose a little, measured 5.7e-4 x CFL over the nine periods, bounded at
//    1.5e-3 x CFL (2.6x), so that a damped update fails. The energy written per step is not the
//    conserved quantity: the kinetic energy belongs to the half step t - dt/2 and the strain
//    energy to t, so within each period it oscillates by
//    E(0) (cos^2(w t - w dt/2) - cos^2(w t)) = E(0) sin(w dt / 2) sin(2 w t - w dt / 2): the
//    peak of E(t)/E(0) - 1 must be sin(w dt / 2) within 5 % (measured 0.3 % at CFL 0.1 to 2.4 %
//    at 0.95), which checks the staggering itself. Above the limit: a `cfl` >= 1 and a
//    fixed `dt` above h / c_p are input errors (exit 2) naming the key; a fixed step that starts
//    legal but whose Courant number dt (c_p + |v|) / h exceeds 1 because the points move (here a
//    uniform drift of 0.5 m/s at dt = 0.97 h / c_p, Courant 1.02) is stopped before the step is
//    taken, exit 3, with the step, time and offending particle named, and the last good frame kept.
//  * Implicit Newmark (beta = 1/4, gamma = 1/2) at 1x to 100x the explicit limit h / c over ten
//    periods: the trapezoidal rule conserves the energy of the linear grid system exactly, so
//    the energy may never grow: E(end) <= E(0) (1 + 1e-9). The energy is evaluated on the
//    particles, whose velocity update from the grid (FLIP) dissipates a little (measured 0.13 %,
//    1.06 %, 2.08 % and 1.52 % at 1x, 10x, 30x and 100x over ten periods: each bounded at 2.5x
//    its own) and whose representation of the grid energy fluctuates within a step (measured
//    1.8e-4 at 1x: bounded at 5e-4, 2.8x).
//    Period elongation (omega dt)^2 / 12 makes the largest steps slow, not unstable.
#include "cases.hpp"
#include "histories.hpp"
#include "references.hpp"

#include "talus/core/errors.hpp"
#include "talus/io/csv.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <map>
#include <numbers>

namespace talus::verify_cases {

namespace {

using references::kBarDensity;
using references::kBarLength;
using references::kBarYoung;

constexpr int kCells = 32;

double peak_growth(const std::vector<double>& energy) {
  return *std::max_element(energy.begin(), energy.end()) / energy.front() - 1.0;
}

/// Mean of `values` over the rows whose time lies in [from, to).
double mean_over(const CsvTable& series, const std::string& column, double from, double to) {
  const auto& t = series.column("time");
  const auto& v = series.column(column);
  double sum = 0, n = 0;
  for (std::size_t i = 0; i < t.size(); ++i)
    if (t[i] >= from && t[i] < to) {
      sum += v[i];
      n += 1;
    }
  return sum / n;
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

/// Whether reading the case with `overrides` is refused as bad input naming `key`.
bool refused_at_input(const VerificationContext& ctx, const std::vector<std::string>& overrides,
                      const std::string& key) {
  try {
    load_verification_case(ctx, overrides);
  } catch (const InputError& e) {
    return contains(e.what(), key);
  }
  return false;
}

} // namespace

VerificationCase stability_explicit_cfl() {
  VerificationCase vc;
  vc.name = "stability_explicit_cfl";
  vc.scene = "vibrating_bar";
  vc.description = "Explicit MUSL/FLIP/GIMP vibrating bar (32 cells) at CFL 0.1 to 0.95: energy "
                   "growth under 1 %; CFL >= 1 and a fixed dt above h/c_p refused at input; a "
                   "fixed dt whose Courant number the motion pushes above 1 stopped with exit 3.";
  vc.tiers = {"stability"};
  vc.run = [](const VerificationContext& ctx) {
    std::vector<Check> checks;
    HistoryPlot plot;
    const double h = kBarLength / kCells;
    const double c = std::sqrt(kBarYoung / kBarDensity);
    const double period = 4.0 * kBarLength / c;
    const double omega = 2.0 * std::numbers::pi / period;
    for (const double cfl : {0.1, 0.25, 0.5, 0.75, 0.9, 0.95}) {
      auto overrides = references::vibrating_bar_overrides(kCells);
      overrides.push_back(fmt::format("time.cfl={:g}", cfl));
      overrides.push_back(fmt::format("time.end_time={:g}", 10 * period));
      overrides.push_back("output.every_steps=100000");
      const auto dir = ctx.out_dir / fmt::format("cfl_{:g}", cfl);
      run_quiet(load_verification_case(ctx, overrides), dir, ctx.threads);
      const CsvTable series = read_csv(dir / "timeseries.csv");
      const auto& energy = series.column("total_energy");
      const double growth = mean_over(series, "total_energy", 9 * period, 10 * period) /
                                mean_over(series, "total_energy", 0, period) -
                            1.0;
      const double half_phase = 0.5 * omega * cfl * h / c; // w dt / 2
      const double sampling = 2.0 * half_phase * (cfl * h / c) / period;
      checks.push_back(within_check(fmt::format("CFL {:g}: period-mean E, 10th / 1st - 1", cfl),
                                    growth, -1.5e-3 * cfl, sampling,
                                    "no growth beyond a period mean's sampling error; loss "
                                    "2.6x the measured 5.7e-4 CFL"));
      checks.push_back(relative_check(fmt::format("CFL {:g}: max E(t)/E(0) - 1", cfl),
                                      peak_growth(energy), std::sin(half_phase), 0.05,
                                      "half-step staggering: sin(w dt / 2)"));
      plot.add_column("E(t) / E(0) - 1", fmt::format("CFL {:g}", cfl), series, "total_energy",
                      true);
    }
    checks.push_back(holds_check("CFL 1.2 refused at input",
                                 refused_at_input(ctx, {"time.cfl=1.2"}, "time.cfl"),
                                 "InputError (exit 2) naming time.cfl"));
    checks.push_back(holds_check(
        "fixed dt = 1.05 h/c_p refused at input",
        refused_at_input(ctx, {fmt::format("time.dt={:.17g}", 1.05 * h / c)}, "time.dt"),
        "InputError (exit 2) naming time.dt"));

    // Legal at input (0.97 h/c_p), but the drift makes the Courant number 0.97 (10.5 / 10).
    auto drift = references::vibrating_bar_overrides(kCells);
    drift.insert(drift.end(), {fmt::format("time.dt={:.17g}", 0.97 * h / c),
                               "bodies[0].velocity=[0.5, 0]", "boundaries.x_min=free"});
    const auto dir = ctx.out_dir / "courant_above_1";
    RunOptions options{dir, true, ctx.threads, false};
    const RunResult r = run_case(load_verification_case(ctx, drift), options);
    const bool named = contains(r.message, "Courant number") && contains(r.message, "particle") &&
                       contains(r.message, "step") && contains(r.message, "t = ");
    checks.push_back(absolute_check("Courant 1.02 while stepping: exit code", r.exit_code,
                                    kExitNumerical, 0.0, r.message.substr(0, 200)));
    checks.push_back(holds_check("Courant 1.02: message names step, time, particle", named,
                                 "field, particle, step and time"));
    checks.push_back(
        report_only("Courant 1.02: steps taken before the stop", static_cast<double>(r.steps)));
    plot.write(ctx.out_dir, "stability_explicit_cfl",
               "Explicit vibrating bar, 32 cells: energy at CFL 0.1 - 0.95");
    return checks;
  };
  return vc;
}

VerificationCase stability_implicit_dt() {
  VerificationCase vc;
  vc.name = "stability_implicit_dt";
  vc.scene = "vibrating_bar";
  vc.description = "Implicit Newmark vibrating bar (32 cells) over ten periods at 1x to 100x "
                   "the explicit limit h/c: no energy growth.";
  vc.tiers = {"stability"};
  vc.run = [](const VerificationContext& ctx) {
    std::vector<Check> checks;
    HistoryPlot plot;
    const double h = kBarLength / kCells;
    const double c = std::sqrt(kBarYoung / kBarDensity);
    // FLIP's measured loss over ten periods at each step size (see the top of the file).
    const std::map<double, double> measured_loss = {
        {1.0, 1.25e-3}, {10.0, 1.06e-2}, {30.0, 2.08e-2}, {100.0, 1.52e-2}};
    for (const auto& [factor, loss] : measured_loss) {
      auto overrides = references::vibrating_bar_overrides(kCells);
      overrides.insert(overrides.end(),
                       {"analysis=implicit_dynamic", "time.end_time=100",
                        fmt::format("time.dt={:.17g}", factor * h / c), "output.every_steps=1000"});
      const auto dir = ctx.out_dir / fmt::format("dt_{:g}x", factor);
      run_quiet(load_verification_case(ctx, overrides), dir, ctx.threads);
      const CsvTable series = read_csv(dir / "timeseries.csv");
      const auto& energy = series.column("total_energy");
      const std::string at = fmt::format("dt = {:g} h/c", factor);
      checks.push_back(within_check(
          at + ": E(end)/E(0) - 1", energy.back() / energy.front() - 1.0, -2.5 * loss, 1e-9,
          fmt::format("trapezoidal rule: no growth; FLIP's loss <= 2.5x the measured {:.3g}",
                      loss)));
      checks.push_back(at_most_check(at + ": max E(t)/E(0) - 1", peak_growth(energy), 5e-4,
                                     "transients of the particle energy; 2.8x measured"));
      plot.add_column("E(t) / E(0) - 1", at, series, "total_energy", true);
      plot.add_column("centre-of-mass momentum", at, series, "momentum_x", false);
    }
    plot.write(ctx.out_dir, "stability_implicit_dt",
               "Implicit Newmark vibrating bar, 32 cells, dt up to 100 h/c");
    return checks;
  };
  return vc;
}

} // namespace talus::verify_cases
