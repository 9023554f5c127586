// Stress recovery on the reference talk's cantilever (verification/grashof.yaml: L = 8, D = 1,
// nu = 0, tip force P = -1 N, i.e. downwards; implicit quasi-static, GIMP, 2 x 2 points per
// cell) with E = 3e8 instead of the talk's 3e5. The beam is statically determinate, so its
// stresses do not depend on E, but its rotation does: at E = 3e5 the mid-span section turns by
// 1e-3 rad, and the small-strain linear law (W(sym F - I), not objective) carries half of that
// rotation of the bending stress into the shear, theta sigma_xx / 2 = 1.5 % of the peak shear
// at the surface, a floor of the comparison with the small-deformation references that
// refinement cannot remove (measured: the interior grid-node error stalled at 1.1 % from 16 to
// 32 cells, observed order 0.25). At E = 3e8 it turns by 1e-6. At mid-span x = L/2, through the
// depth, three shear-stress profiles are compared with Grashof's (Jourawski's) parabola tau_xy(y) =
// 3P/(2D) (1 - 4y^2/D^2):
//   (a) raw particle stress of the column of points nearest mid-span (first column x0 >= L/2),
//   (b) grid-node stress sigma_i = sum_p sigma_p Phi_ip m_p / m_i on the node line x = L/2,
//   (c) smoothed particle stress sigma_p^s = sum_i sigma_i Phi_ip of the column of (a);
// and the bending stress against Navier, sigma_xx = -P (L - x) y / I. (Both formulas take P as
// the signed vertical tip force, so the downward load gives negative shear and tension on top.)
// Errors are discrete relative L2 norms over the sample points, sqrt(sum e^2 / sum ref^2), with
// y measured from the deflected neutral axis (the grid nodes are fixed in space; the section has
// moved by the mean displacement of the column's points, 0.2 % of a cell at 8 cells/depth).
//
// Checks and why these bounds:
//  * Reference resolution 8 cells through the depth (the cantilever verification's). The
//    recovered shear (b) must be within 5 % (the bound; measured 3.0 %) and the recovered
//    bending stress (b) within 0.5 % (2.5x the measured 0.20 %) over the sample points whose
//    shape-function support lies inside the beam, |y| <= D/2 - h. At the two free surfaces the
//    projection averages one-sidedly (the node's support is cut by the surface), which biases
//    any field by O(h) there whatever the particle stresses are; that band is the formula's,
//    not MPM's noise, and shrinks as h -> 0.
//  * Observed orders from 4 to 8 to 16 cells/depth (32 in the full tier). Raw particle shear
//    (a): first order, [0.8, 1.2] (measured 0.96 to 0.99: the parasitic shear of bending, of
//    opposite sign in neighbouring point columns, is O(h)). Recovered (b) and (c) inside the
//    band: second order, [1.5, 2.5] (measured 1.83 to 1.96): the projection averages the
//    alternating O(h) part away and leaves the displacement's order. Full depth, surface band
//    included: an O(h) bias on a band of width h adds h^1.5 to the L2 norm, so [1.2, 1.8]
//    (measured 1.30 to 1.47, rising towards 1.5).
//  * The raw particle errors are reported, not bounded: the talk's point is that they are large.
//  * Linear hats at the reference resolution get the same bounds: the talk used them.
// The report shows the three shear profiles against the parabola (grashof.png, drawn by
// scripts/plot_grashof.py).
#include "cases.hpp"
#include "references.hpp"
#include "talus/post/python_script.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <fstream>
#include <sstream>

namespace talus::verify_cases {

namespace {

using references::kBeamDepth;
using references::kBeamInertia;
using references::kBeamLength;

constexpr double kTipForce = -1.0; // N per unit thickness, verification/grashof.yaml
constexpr double kMidSpan = 0.5 * kBeamLength;

double grashof_shear(double y) {
  return 1.5 * kTipForce / kBeamDepth * (1.0 - 4.0 * y * y / (kBeamDepth * kBeamDepth));
}
double navier_bending(double x, double y) {
  return -kTipForce * (kBeamLength - x) * y / kBeamInertia;
}

/// Stress samples through the depth at mid-span; y from the deflected neutral axis.
struct Profile {
  std::vector<double> y, shear, bending;
  /// Relative L2 errors of shear and bending against the analytical profiles, over the samples
  /// with |y| <= limit.
  std::pair<double, double> errors(double limit) const {
    double es = 0, rs = 0, eb = 0, rb = 0;
    for (std::size_t k = 0; k < y.size(); ++k) {
      if (std::abs(y[k]) > limit * (1.0 + 1e-9))
        continue;
      const double ts = grashof_shear(y[k]), tb = navier_bending(kMidSpan, y[k]);
      es += (shear[k] - ts) * (shear[k] - ts);
      rs += ts * ts;
      eb += (bending[k] - tb) * (bending[k] - tb);
      rb += tb * tb;
    }
    return {std::sqrt(es / rs), std::sqrt(eb / rb)};
  }
};

struct MidSpan {
  Profile raw, grid, smoothed;
};

MidSpan mid_span_profiles(const ResultsReader& results) {
  const Index last = results.frame_count() - 1;
  Index n = 0, cols = 0;
  const auto x0 = results.read(0, "position", &n, &cols);
  const auto x1 = results.read(last, "position", &n, &cols);
  const auto raw = results.read(last, "stress", &n, &cols);
  const auto smoothed = results.read(last, "stress_smoothed", &n, &cols);
  auto at = [](const std::vector<double>& v, Index row, Index width, int c) {
    return v[static_cast<std::size_t>(row * width + c)];
  };
  // The column of points nearest mid-span: the smallest initial x at or beyond L/2.
  double column_x = 1e300;
  for (Index p = 0; p < n; ++p)
    if (at(x0, p, 2, 0) >= kMidSpan)
      column_x = std::min(column_x, at(x0, p, 2, 0));
  std::vector<Index> column;
  double deflection = 0;
  for (Index p = 0; p < n; ++p)
    if (std::abs(at(x0, p, 2, 0) - column_x) < 1e-9) {
      column.push_back(p);
      deflection += at(x1, p, 2, 1) - at(x0, p, 2, 1);
    }
  deflection /= static_cast<double>(column.size());
  std::sort(column.begin(), column.end(),
            [&](Index a, Index b) { return at(x0, a, 2, 1) < at(x0, b, 2, 1); });
  MidSpan m;
  // Tensor6 columns: xx 0, xy 1.
  for (const Index p : column) {
    const double y = at(x0, p, 2, 1);
    m.raw.y.push_back(y);
    m.raw.shear.push_back(at(raw, p, 6, 1));
    m.raw.bending.push_back(at(raw, p, 6, 0));
    m.smoothed.y.push_back(y);
    m.smoothed.shear.push_back(at(smoothed, p, 6, 1));
    m.smoothed.bending.push_back(at(smoothed, p, 6, 0));
  }
  // Grid nodes on the line x = L/2 whose position lies in the deflected section (the grid/
  // group covers the box of nodes the beam reaches, from its own origin).
  std::istringstream origin_text(results.frame_attribute(last, "grid", "origin"));
  double ox = 0, oy = 0;
  origin_text >> ox >> oy;
  const double h = std::stod(results.metadata_string("cell_size"));
  Index ny = 0, nx = 0;
  const auto grid_stress = results.read(last, "grid/stress", &ny, &cols); // ny * nx rows
  const auto grid_mass = results.read(last, "grid/mass", &ny, &nx);
  const Index i = std::lround((kMidSpan - ox) / h);
  for (Index j = 0; j < ny; ++j) {
    const double y = oy + h * static_cast<double>(j) - deflection;
    if (std::abs(y) > 0.5 * kBeamDepth + 0.5 * h || at(grid_mass, j, nx, static_cast<int>(i)) <= 0)
      continue;
    m.grid.y.push_back(y);
    m.grid.shear.push_back(at(grid_stress, j * nx + i, 6, 1));
    m.grid.bending.push_back(at(grid_stress, j * nx + i, 6, 0));
  }
  return m;
}

/// The profiles of one resolution and the analytical parabola, for scripts/plot_grashof.py.
void write_profiles_csv(const std::filesystem::path& file, const MidSpan& m) {
  std::ofstream out(file);
  out << "kind,y,tau_xy\n";
  for (int k = 0; k <= 100; ++k) {
    const double y = kBeamDepth * (-0.5 + k / 100.0);
    out << fmt::format("analytical,{:.17g},{:.17g}\n", y, grashof_shear(y));
  }
  const std::pair<const char*, const Profile*> kinds[] = {
      {"raw", &m.raw}, {"grid", &m.grid}, {"smoothed", &m.smoothed}};
  for (const auto& [kind, profile] : kinds)
    for (std::size_t k = 0; k < profile->y.size(); ++k)
      out << fmt::format("{},{:.17g},{:.17g}\n", kind, profile->y[k], profile->shear[k]);
}

} // namespace

VerificationCase grashof() {
  VerificationCase vc;
  vc.name = "grashof";
  vc.distributable = true;
  vc.description =
      "Stress recovery (Andersen 2013) on the talk's cantilever (L = 8, D = 1, nu = 0, E = 3e8 "
      "so that the section's rotation does not enter the small-strain references, "
      "tip force -1 N): shear through the depth at mid-span from raw particle stress, grid-node "
      "stress and smoothed particle stress against Grashof's parabola, and the bending stress "
      "against Navier, under refinement. Checked errors exclude the free-surface band of width h "
      "(one-sided projection); the full-depth errors are reported beside them.";
  vc.tiers = {"fast", "full"};
  vc.run = [](const VerificationContext& ctx) {
    std::vector<Check> checks;
    std::vector<int> depth_cells = {4, 8, 16};
    if (ctx.tier == "full")
      depth_cells.push_back(32);
    constexpr int kReference = 8;
    std::vector<double> raw_errors, grid_errors, smoothed_errors, grid_full, smoothed_full;
    auto run = [&](int n, const std::string& shape) {
      const double h = kBeamDepth / n;
      const CaseSpec spec = load_verification_case(
          ctx, {fmt::format("grid.cell_size={:.17g}", h), "solver.shape=" + shape});
      const auto dir = ctx.out_dir / fmt::format("{}_{}cells", shape, n);
      run_quiet(spec, dir, ctx.threads);
      return std::pair{mid_span_profiles(ResultsReader(dir / "run.h5")), h};
    };
    for (const int n : depth_cells) {
      const auto [m, h] = run(n, "gimp");
      const double interior = 0.5 * kBeamDepth - h, full = 0.5 * kBeamDepth + h;
      const auto [raw_shear, raw_bending] = m.raw.errors(full);
      const auto [grid_shear, grid_bending] = m.grid.errors(interior);
      const auto [smooth_shear, smooth_bending] = m.smoothed.errors(interior);
      raw_errors.push_back(raw_shear);
      grid_errors.push_back(grid_shear);
      smoothed_errors.push_back(smooth_shear);
      grid_full.push_back(m.grid.errors(full).first);
      smoothed_full.push_back(m.smoothed.errors(full).first);
      const std::string at = fmt::format("{} cells/depth", n);
      checks.push_back(report_only("shear (a) raw particles, " + at, raw_shear,
                                   "relative L2 over the column, full depth"));
      if (n == kReference) {
        checks.push_back(at_most_check("shear (b) grid nodes, " + at, grid_shear, 0.05,
                                       "relative L2, |y| <= D/2 - h"));
        checks.push_back(at_most_check("bending (b) grid nodes, " + at, grid_bending, 0.005,
                                       "relative L2, |y| <= D/2 - h"));
        write_profiles_csv(ctx.out_dir / "grashof_profiles.csv", m);
      } else {
        checks.push_back(
            report_only("shear (b) grid nodes, " + at, grid_shear, "relative L2, |y| <= D/2 - h"));
        checks.push_back(report_only("bending (b) grid nodes, " + at, grid_bending,
                                     "relative L2, |y| <= D/2 - h"));
      }
      checks.push_back(report_only("shear (c) smoothed particles, " + at, smooth_shear,
                                   "relative L2, |y| <= D/2 - h"));
      checks.push_back(report_only("bending (c) smoothed particles, " + at, smooth_bending,
                                   "relative L2, |y| <= D/2 - h"));
      checks.push_back(report_only("shear (b) grid, full depth, " + at, grid_full.back(),
                                   "surface nodes included"));
      checks.push_back(report_only("shear (c) smoothed, full depth, " + at, smoothed_full.back(),
                                   "surface points included"));
      checks.push_back(report_only("bending (b) grid, full depth, " + at,
                                   m.grid.errors(full).second, "surface nodes included"));
      checks.push_back(
          report_only("bending (a) raw particles, " + at, raw_bending, "relative L2, full depth"));
    }
    auto orders = [&](const std::string& what, const std::vector<double>& e, double low,
                      double high, const char* theory) {
      for (std::size_t k = 1; k < e.size(); ++k)
        checks.push_back(within_check(
            fmt::format("{} observed order {}->{} cells", what, depth_cells[k - 1], depth_cells[k]),
            observed_order(e[k - 1], e[k]), low, high, theory));
    };
    orders("shear (a) raw", raw_errors, 0.8, 1.2, "theory 1: the parasitic shear is O(h)");
    orders("shear (b)", grid_errors, 1.5, 2.5, "theory 2");
    orders("shear (c)", smoothed_errors, 1.5, 2.5, "theory 2");
    orders("shear (b) full depth", grid_full, 1.2, 1.8, "theory 1.5: O(h) surface band");
    orders("shear (c) full depth", smoothed_full, 1.2, 1.8, "theory 1.5: O(h) surface band");

    // Linear hats, as in the talk, at the reference resolution.
    const auto [m, h] = run(kReference, "linear");
    const std::string at = fmt::format("linear hats, {} cells/depth", kReference);
    checks.push_back(at_most_check("shear (b) grid nodes, " + at,
                                   m.grid.errors(0.5 * kBeamDepth - h).first, 0.05,
                                   "relative L2, |y| <= D/2 - h; 1.6x the measured 0.030"));
    checks.push_back(at_most_check("bending (b) grid nodes, " + at,
                                   m.grid.errors(0.5 * kBeamDepth - h).second, 0.005,
                                   "relative L2, |y| <= D/2 - h; 2.5x the measured 0.0020"));
    checks.push_back(report_only("shear (a) raw particles, " + at,
                                 m.raw.errors(0.5 * kBeamDepth + h).first,
                                 "relative L2, full depth"));

    run_python_script("plot_grashof.py", {(ctx.out_dir / "grashof_profiles.csv").string(),
                                          (ctx.out_dir / "grashof.png").string(),
                                          fmt::format("{} cells/depth", kReference)});
    return checks;
  };
  return vc;
}

} // namespace talus::verify_cases
