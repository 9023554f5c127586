// The reference talk's cantilever (L = 8, D = 1, E = 3e5, nu = 0), implicit quasi-static; the
// tip load is a traction on the end face (applied at the face, see grid/surface_load.hpp).
//  * Linear range, tip shear load P = 1: the mean vertical displacement of the tip column of
//    points against Timoshenko & Goodier, u_y(x) = -P / (6 E I) (D^2 x + (3L - x) x^2) for
//    nu = 0 (y-independent), at 4, 8 and 16 cells through the depth. Measured errors 0.72 %,
//    0.062 %, 0.10 %: beyond 8 cells the error is the model difference of the fully clamped
//    root (the analytical solution lets the root section warp), not a discretisation error.
//    So the 8-cell deflection must lie within 0.2 % (3x its error, twice the 0.10 % of the
//    model difference), and convergence is checked on the deflections themselves: the observed
//    order of the successive differences log2(|u8 - u4| / |u16 - u8|) must lie in [1.5, 2.5]
//    (displacements of the bilinear-like MPM field converge at second order; measured 2.01).
//  * Large deflection, Hencky material, dead tip load P L^2 / (E I) = alpha: the displacement
//    of the tip column of points against the elastica (theta'' = -alpha cos(theta), solved by
//    shooting with RK4) at the same arclength; at alpha = 0.25 (10 load steps, the talk's
//    section) and alpha = 2 (50 load steps; the tip sweeps across dozens of cells and the
//    ghost penalty keeps the tangent regular). The elastica is inextensible and shear-rigid,
//    which a thick continuum beam is not: at L/D = 8 and alpha = 2 the measured deflection lies
//    2.2 % above it at 8 and at 16 cells, refinement does not remove it, and a Reissner beam with
//    shear flexibility accounts for about half. So alpha = 2 runs on a beam of half the depth
//    (L/D = 16, references::kSlenderBeamDepth), where shear and fibre strain are 4x and 2x
//    smaller. Tolerances from the measurement and that model difference: alpha = 0.25, v within
//    2 % (measured 1.04 %, of which Timoshenko's shear deflection 3 E I / (k G A L^2) = 0.94 %),
//    u within 0.5 % (measured 0.14 %); alpha = 2, v within 2 % (measured 0.89 %), u within 3 %
//    (measured 1.5 %). Newton must converge quadratically at alpha = 0.25: on every load step
//    the last iterate above the round-off floor satisfies log r_{k+1} / log r_k >= 1.8 (at
//    alpha = 2 the beam is so compliant that the quadratic constant is large and this
//    scale-dependent measure does not apply); at alpha = 2 at most 6 Newton iterations per load
//    step (measured 4; an inconsistent tangent needs tens).
#include "cases.hpp"
#include "newton_log.hpp"
#include "references.hpp"

#include <cmath>
#include <fmt/format.h>
#include <fstream>
#include <sstream>

namespace talus::verify_cases {

namespace {

using references::kBeamDepth;
using references::kBeamInertia;
using references::kBeamLength;
using references::kBeamYoung;

/// The bounds that depend on the shape: the linear tip deflection at 8 cells and the tip
/// shortening at alpha = 0.25 (uGIMP's, justified above).
struct CantileverBounds {
  double tip_deflection = 0.002;
  double shortening = 0.005;
};

/// The cantilever's checks with `shape` (empty: the scene's uGIMP), its runs below
/// out_dir / shape and every quantity named after it.
std::vector<Check> cantilever_checks(const VerificationContext& ctx, const std::string& shape,
                                     const CantileverBounds& bounds = {}) {
  const auto out = shape.empty() ? ctx.out_dir : ctx.out_dir / shape;
  const auto with_shape = [&](std::vector<std::string> overrides) {
    if (!shape.empty())
      overrides.push_back("solver.shape=" + shape);
    return overrides;
  };
  std::vector<Check> checks;
  const std::vector<int> depth_cells = {4, 8, 16};
  std::vector<double> deflections;
  for (const int n : depth_cells) {
    const double h = kBeamDepth / n;
    const CaseSpec spec =
        load_verification_case(ctx, with_shape({fmt::format("grid.cell_size={:.17g}", h)}));
    const auto dir = out / fmt::format("linear_{}cells", n);
    run_quiet(spec, dir, ctx.threads);
    double x = 0;
    const Vec3 u = references::tip_column_displacement(ResultsReader(dir / "run.h5"), &x);
    const double reference = references::cantilever_deflection(x, 1.0);
    // Scaled to the tip, so that the three resolutions (whose tip columns sit at L - h/4)
    // compare one quantity.
    deflections.push_back(u.y() / reference * references::cantilever_deflection(kBeamLength, 1.0));
    checks.push_back(n == 8 ? relative_check("tip deflection, 8 cells/depth", u.y(), reference,
                                             bounds.tip_deflection,
                                             "Timoshenko-Goodier at the tip column")
                            : report_only(fmt::format("tip deflection error, {} cells/depth", n),
                                          std::abs(u.y() / reference - 1.0)));
  }
  const double coarse_step = std::abs(deflections[1] - deflections[0]);
  const double fine_step = std::abs(deflections[2] - deflections[1]);
  checks.push_back(within_check("observed order of the deflection changes 4->8->16",
                                observed_order(coarse_step, fine_step), 1.5, 2.5,
                                "self-convergence; theory 2"));

  for (const auto& [alpha, steps] : {std::pair{0.25, 10}, std::pair{2.0, 50}}) {
    // alpha = 0.25 on the talk's section (L/D = 8), alpha = 2 on the slender one (L/D = 16).
    auto overrides = references::large_deflection_overrides(alpha, steps, 8);
    if (alpha < 1)
      overrides.insert(
          overrides.end(),
          {"bodies[0].min=[0, -0.5]", "bodies[0].max=[8, 0.5]", "grid.cell_size=0.125",
           fmt::format("tractions[0].traction=[0, {:.17g}]",
                       -alpha * kBeamYoung * kBeamInertia / (kBeamLength * kBeamLength))});
    const CaseSpec large = load_verification_case(ctx, with_shape(overrides));
    const auto dir = out / fmt::format("elastica_alpha_{:g}", alpha);
    const RunResult run = run_quiet(large, dir, ctx.threads);
    double x = 0;
    const Vec3 u = references::tip_column_displacement(ResultsReader(dir / "run.h5"), &x);
    const references::Elastica ref = references::elastica(alpha, x / kBeamLength);
    const std::string note = fmt::format("L/D = {:g}, 8 cells/depth, Hencky, {} load steps",
                                         alpha < 1 ? 8.0 : 16.0, steps);
    checks.push_back(relative_check(fmt::format("elastica v/L (alpha {:g})", alpha),
                                    -u.y() / kBeamLength, ref.v_over_L, 0.02, note));
    checks.push_back(relative_check(
        fmt::format("elastica u/L (alpha {:g})", alpha), -u.x() / kBeamLength, ref.u_over_L,
        alpha < 1 ? bounds.shortening : 0.03, "tip shortening, same point"));
    if (alpha < 1)
      checks.push_back(newton_order_check("Newton order (worst step)", dir / "newton.log", 1.8,
                                          "log r_{k+1} / log r_k in the quadratic regime"));
    else
      checks.push_back(at_most_check(
          fmt::format("Newton iterations per step (alpha {:g})", alpha),
          run.extra.at("newton_iterations_max_per_step"), 6.0,
          fmt::format("largest; {:g} in all over {} steps, {:g} cut-backs",
                      run.extra.at("newton_iterations"), steps, run.extra.at("cutbacks"))));
  }
  if (!shape.empty())
    for (Check& c : checks)
      c.quantity = shape + ": " + c.quantity;
  return checks;
}

} // namespace

VerificationCase cantilever() {
  VerificationCase vc;
  vc.name = "cantilever";
  vc.distributable = true;
  vc.description =
      "The talk's cantilever (L = 8, D = 1, E = 3e5, nu = 0), implicit quasi-static with GIMP: "
      "tip deflection in the linear range against Timoshenko-Goodier under refinement, and "
      "large deflections (P L^2 / EI = 0.25 and 2, Hencky) against the elastica with Newton's "
      "convergence order and iteration count.";
  vc.tiers = {"fast", "full"};
  vc.run = [](const VerificationContext& ctx) { return cantilever_checks(ctx, {}); };
  return vc;
}

// The same rows for each shape beside uGIMP (issue 21: the cantilever and elastica rows for
// each shape), with uGIMP's bounds but two for the splines. Measured, cpGIMP and CPDI (equal in
// the linear range: the undeformed domains of 2 x 2 points per cell never straddle a node),
// elastica 1.02 / 0.10 % and 0.59 / 0.66 % for CPDI; cpGIMP: tip deflection at
// 8 cells +0.06 %, order 2.01, elastica 1.03 / 0.12 % (alpha 0.25), 0.87 / 1.5 % (alpha 2),
// Newton order 1.89. The splines deflect more at a given resolution: +1.7, +0.55, +0.26 % at
// 4, 8, 16 cells (order 1.97, so the Richardson limit is +0.16 %, within uGIMP's root-model
// difference of 0.10 %), and shorten the tip at alpha = 0.25 by 0.78 % more than the elastica
// (v 1.37 %); the other rows as uGIMP's (alpha 2: 0.66-0.82 % and 0.77-1.25 %; Newton order
// 1.84-1.85, 4 iterations per step). Their bounds are 2.2x and 1.9x those measurements: the tip
// deflection within 1.2 % at 8 cells, the shortening within 1.5 %.
VerificationCase cantilever_shapes() {
  VerificationCase vc;
  vc.name = "cantilever_shapes";
  vc.scene = "cantilever";
  vc.description = "The cantilever's linear and elastica rows with cpGIMP, CPDI and quadratic "
                   "and cubic B-splines.";
  vc.tiers = {"fast", "full"};
  vc.run = [](const VerificationContext& ctx) {
    std::vector<Check> checks;
    for (const std::string shape : {"cpgimp", "cpdi", "bspline2", "bspline3"}) {
      const bool spline = shape == "bspline2" || shape == "bspline3";
      auto c = cantilever_checks(ctx, shape,
                                 spline ? CantileverBounds{0.012, 0.015} : CantileverBounds{});
      checks.insert(checks.end(), c.begin(), c.end());
    }
    return checks;
  };
  return vc;
}

} // namespace talus::verify_cases
