// Colliding elastic discs (the reference talk's material). Three physical truths:
//  * linear momentum: no external force acts, so |P(t)| stays at round-off. Each step adds at
//    most a few machine epsilons of sum(m |v|); the bound is 10 * steps * eps * sum(m |v0|).
//  * mirror symmetry about x + y = 1: every point of one disc has a partner in the other
//    at (1 - y, 1 - x). Only round-off breaks it: bound 1e-9 cell sizes.
//  * energy: the collision is elastic; the loss of kinetic + strain energy over the collision
//    with FLIP MUSL must stay below 5 % (the bound) at the reference resolution.
#include "cases.hpp"

#include "talus/io/csv.hpp"

#include <cmath>
#include <fmt/format.h>
#include <limits>

namespace talus::verify_cases {

namespace {

Vec2 mirror(const Vec2& x) {
  return {1.0 - x.y(), 1.0 - x.x()};
}

} // namespace

VerificationCase colliding_discs() {
  VerificationCase vc;
  vc.name = "colliding_discs";
  vc.description = "Two neo-Hookean discs (rho0 = 20, E = 1e5, nu = 0.3) collide and rebound: "
                   "momentum conservation, mirror symmetry about x + y = 1, and energy loss "
                   "over the collision (GIMP, MUSL, FLIP).";
  vc.tiers = {"fast", "full"};
  vc.run = [](const VerificationContext& ctx) {
    const CaseSpec spec = load_verification_case(ctx);
    const auto dir = ctx.out_dir / "run";
    const RunResult r = run_quiet(spec, dir, ctx.threads);
    const CsvTable series = read_csv(dir / "timeseries.csv");
    ResultsReader results(dir / "run.h5");

    Index rows = 0, cols = 0;
    const auto mass = results.read(0, "mass", &rows, &cols);
    const auto x0 = results.read(0, "position", &rows, &cols);
    const auto v0 = results.read(0, "velocity", &rows, &cols);
    const Index n = rows;
    double momentum_scale = 0;
    for (Index p = 0; p < n; ++p)
      momentum_scale +=
          mass[static_cast<std::size_t>(p)] *
          std::hypot(v0[static_cast<std::size_t>(2 * p)], v0[static_cast<std::size_t>(2 * p + 1)]);
    double max_momentum = 0;
    const auto& px = series.column("momentum_x");
    const auto& py = series.column("momentum_y");
    for (std::size_t i = 0; i < px.size(); ++i)
      max_momentum = std::max(max_momentum, std::hypot(px[i], py[i]));
    const double eps = std::numeric_limits<double>::epsilon();
    const double momentum_bound = 10.0 * static_cast<double>(r.steps) * eps;

    // Partner of each point under the mirror map, found on the initial lattice.
    auto at = [](const std::vector<double>& xy, Index p) {
      return Vec2(xy[static_cast<std::size_t>(2 * p)], xy[static_cast<std::size_t>(2 * p + 1)]);
    };
    std::vector<Index> partner(static_cast<std::size_t>(n), -1);
    const double h = spec.grid.cell_size;
    for (Index p = 0; p < n; ++p) {
      const Vec2 target = mirror(at(x0, p));
      for (Index q = 0; q < n; ++q)
        if ((at(x0, q) - target).norm() < 1e-9 * h) {
          partner[static_cast<std::size_t>(p)] = q;
          break;
        }
      if (partner[static_cast<std::size_t>(p)] < 0)
        throw std::runtime_error(fmt::format("point {} has no mirror partner at t = 0", p));
    }
    const Index last = results.frame_count() - 1;
    const auto x_end = results.read(last, "position", &rows, &cols);
    double asymmetry = 0;
    for (Index p = 0; p < n; ++p)
      asymmetry = std::max(
          asymmetry,
          (at(x_end, partner[static_cast<std::size_t>(p)]) - mirror(at(x_end, p))).norm() / h);

    const auto& total = series.column("total_energy");
    const auto& kinetic = series.column("kinetic_energy");
    const double loss = (total.front() - total.back()) / total.front();
    double min_kinetic = total.front();
    for (double k : kinetic)
      min_kinetic = std::min(min_kinetic, k);

    return std::vector<Check>{
        bound_check("max |P(t)| / sum m|v0|", max_momentum / momentum_scale, momentum_bound,
                    fmt::format("10 x steps ({}) x machine epsilon", r.steps)),
        bound_check("mirror asymmetry / h (final)", asymmetry, 1e-9, "round-off only"),
        bound_check("energy loss over collision", loss, 0.05,
                    "(E(0) - E(end)) / E(0), kinetic + strain"),
        report_only("min kinetic / initial energy", min_kinetic / total.front(),
                    "shows the discs really collided"),
        report_only("particles", static_cast<double>(n)),
        report_only("steps", static_cast<double>(r.steps))};
  };
  return vc;
}

} // namespace talus::verify_cases
