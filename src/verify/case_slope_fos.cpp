// Factor of safety of Griffiths & Lane's (1999) example 1 by strength reduction
// (verification/slope_fos.yaml: H = 10 m, 2:1, crest 12 m, firm base at the toe, gamma = 20
// kN/m3, c' = 10 kPa, phi' = 20 deg, E = 1e5 kPa, nu = 0.3), with the formulation whose factor
// converges with the grid: quadratic B-splines without F-bar, associated flow (psi = phi). The
// reference FoS = 1.4 is Griffiths & Lane's finite-element strength reduction, which agrees with
// Bishop & Morgenstern's charts for c'/(gamma H) = 0.05, phi' = 20 deg, D = 1.
//
// Check and why this bound: the 5 % on the reported factor (the midpoint of the final
// bracket) at this one resolution, h = 0.5 m; the convergence under refinement is the full
// tier's slope_fos_refinement (1.414, 1.387, 1.381 at h = 0.5, 0.25, 0.125 m). The bracket is
// 0.02 wide, so the search resolution contributes at most 0.7 % of the 5 %; the rest is the
// discretisation, which at h = 0.5 m puts the factor 2.8 % above Bishop's 1.375 (a kinematic
// approach from above), and the reference's own precision (quoted to two digits). A trial fails
// when the slope's current stiffness falls below min_stiffness = 0.1 (docs/case-format.md).
// Measured: trials 1.414 ([1.406, 1.422], 8 trials, 467 Newton iterations, 6 s of CPU);
// incremental 1.414 (136 iterations, 1.5 s). Bounds on the Newton iterations: twice the
// measured, so that a search that spends its budget on failing trials again fails. The two
// modes within 1 %, about half a bracket. Broken on purpose: uGIMP without F-bar locks (the
// search at h = 0.5 m gave 2.008 with psi = phi on the 1:1.5 slope, 1.60 here with psi = 0).
#include "cases.hpp"
#include "slope_limit_equilibrium.hpp"
#include "talus/io/case_reader.hpp"
#include "talus/solver/strength_reduction.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace talus::verify_cases {

namespace {

constexpr double kReferenceFactor = 1.4; // Griffiths & Lane (1999), example 1

} // namespace

SlopeSection griffiths_lane_section(const CaseSpec& spec) {
  const MaterialSpec& soil = spec.materials.front();
  SlopeSection s;
  s.surface_x = {12, 32};
  s.surface_y = {10, 0};
  s.base_y = 0;
  s.unit_weight = soil.density * spec.gravity.norm();
  s.cohesion = soil.cohesion;
  s.tan_phi = std::tan(soil.friction_angle * std::acos(-1.0) / 180);
  if (spec.water) {
    s.water_level = spec.water->phreatic.front()[1];
    s.water_unit_weight = spec.water->unit_weight;
  }
  return s;
}

namespace {

constexpr int kPerturbations = 3;           ///< E (1 + k step) for k = -3 .. 3
constexpr double kPerturbationStep = 1e-12; ///< relative: of the order of round-off

/// The factors of one plane-strain search repeated under round-off-sized changes of its data.
struct Ensemble {
  std::vector<double> factors;
  /// The member closest to x.
  double nearest(double x) const {
    return *std::min_element(factors.begin(), factors.end(),
                             [x](double a, double b) { return std::abs(a - x) < std::abs(b - x); });
  }
  /// The smallest and the largest member, for the report.
  std::string spread() const {
    const auto [lo, hi] = std::minmax_element(factors.begin(), factors.end());
    return fmt::format("plane strain at E (1 + k {0:g}), k = -{1} .. {1}: {2:.4f} to {3:.4f}",
                       kPerturbationStep, kPerturbations, *lo, *hi);
  }
};

/// The plane-strain search of `spec` with Young's modulus perturbed by k kPerturbationStep.
Ensemble plane_strain_ensemble(const VerificationContext& ctx, const CaseSpec& spec,
                               const std::string& name) {
  Ensemble e;
  for (int k = -kPerturbations; k <= kPerturbations; ++k) {
    CaseSpec perturbed = spec;
    for (MaterialSpec& m : perturbed.materials)
      m.youngs_modulus *= 1 + k * kPerturbationStep;
    e.factors.push_back(
        bracketed_search(ctx, perturbed, fmt::format("{}_k{}", name, k)).fos.value());
  }
  return e;
}

} // namespace

VerificationCase slope_fos() {
  VerificationCase vc;
  vc.name = "slope_fos";
  vc.distributable = true;
  vc.description = "Griffiths & Lane (1999) homogeneous 2:1 slope (c' = 10 kPa, phi' = 20 deg, "
                   "psi = phi, quadratic B-splines): factor of safety by strength reduction "
                   "(c / F, tan phi / F, bisection on F; failure: the current stiffness below "
                   "0.1, a mechanism) against 1.4.";
  vc.tiers = {"fast", "full"};
  vc.run = [](const VerificationContext& ctx) {
    const CaseSpec spec = load_verification_case(ctx);
    const FosRunResult r = bracketed_search(ctx, spec, "search");
    CaseSpec incremental_spec = spec;
    incremental_spec.strength_reduction->mode = StrengthReductionMode::Incremental;
    const FosRunResult inc = bracketed_search(ctx, incremental_spec, "incremental");
    const auto bracket = [&](const FosRunResult& run) {
      return fmt::format("bracket [{:.4f}, {:.4f}], h = {:g} m", run.fos.lower, run.fos.upper,
                         spec.grid.cell_size);
    };
    return std::vector<Check>{
        relative_check("factor of safety", r.fos.value(), kReferenceFactor, 0.05, bracket(r)),
        report_only("search wall time [s]", r.wall_seconds,
                    fmt::format("{} trials; target < 60 s on 2 cores", r.fos.trials.size())),
        report_only("search CPU time [s]", r.cpu_seconds, "user + system, all threads"),
        at_most_check("Newton iterations", static_cast<double>(r.newton_iterations), 930.0,
                      "summed over the trials; 2x the measured 467"),
        relative_check("incremental factor of safety", inc.fos.value(), kReferenceFactor, 0.05,
                       bracket(inc)),
        relative_check("incremental against the trials' factor", inc.fos.value(), r.fos.value(),
                       0.01, "about half a bracket; measured 0"),
        at_most_check("incremental Newton iterations", static_cast<double>(inc.newton_iterations),
                      270.0, "one run; 2x the measured 136"),
        report_only("Bishop's factor (limit equilibrium)",
                    critical_circle(griffiths_lane_section(spec), 0, 0).factor,
                    "the repository's own Bishop on the critical circle"),
        report_only("incremental CPU time / the trials'", inc.cpu_seconds / r.cpu_seconds,
                    fmt::format("{:.2f} s against {:.2f} s", inc.cpu_seconds, r.cpu_seconds))};
  };
  return vc;
}

// Plane-strain equivalence (verification/slope_fos_slab_3d.yaml, full tier): the same slope as
// a 3D prism two cells thick between z rollers. The rollers make the 3D problem the plane-strain
// one, so with the same formulation the search must find the plane-strain factor: within 1 %
// (the bound) at a search resolution of 0.01 (bracket 0.55 % wide).
//  * The formulation. 3D F-bar spreads a cell's volume change over three axes, dF_bar = (J_bar
//    / j)^(1/3) dF, so the slab's points see dF_bar33 != 1 where their displacement has none.
//    Plane strain's default F-bar scales the in-plane block by (J_bar / j)^(1/2) and keeps
//    dF33 = 1 (de Souza Neto et al. 1996); solver.f_bar_out_of_plane is the slab's form, and
//    the two agree point for point to 6e-13 after a plastic step (FBarOutOfPlane, unit tests).
//  * The reference need not be one number. Near the limit a plastic path (Mohr-Coulomb, psi = 0)
//    can amplify round-off: with the earlier displacement criterion (crest beyond 0.1 m) a
//    change of Young's modulus by 1e-12 of itself moved the 2D search's answer between 1.4336
//    and 1.4414. The slab cannot be closer to plane strain than plane strain is to itself, so
//    its factor is compared with the nearest of seven searches at E (1 + k 1e-12),
//    k = -3 .. 3 (an ensemble of the same problem), and the ensemble's spread is reported.
// Measured with the stiffness criterion (one thread): the seven members agree (1.3945 with the
// out-of-plane F-bar, 1.4570 without); the slab 1.3945 with F-bar ([1.3906, 1.3984], 9 trials,
// 421 Newton iterations, 914 s), equal, and 1.4648 without (171 s), +0.54 %: one bracket step.
// Plane strain's default F-bar is reported: 1.3867, the slab +0.56 % (with the displacement
// criterion +2.8 %, which the check would have failed).
// The elastic slab is the plane-strain beam to 1e-11 (cantilever_slab_3d).
VerificationCase slope_fos_slab_3d() {
  VerificationCase vc;
  vc.name = "slope_fos_slab_3d";
  vc.description = "The Griffiths & Lane slope as a 3D slab between z rollers: the strength "
                   "reduction search gives the plane-strain factor of safety of the same "
                   "formulation, with and without F-bar.";
  vc.tiers = {"full"};
  vc.run = [](const VerificationContext& ctx) {
    const std::string plane_strain = (verification_dir() / "slope_fos.yaml").string();
    const std::string resolution = "strength_reduction.tolerance=0.01"; // the slab's own
    // The slab's formulation (uGIMP, psi = 0), not the plane-strain scene's.
    const auto plane = [&](std::vector<std::string> keys) {
      keys.insert(keys.end(), {resolution, "solver.shape=gimp", "materials.0.dilation_angle=0"});
      return read_case_file(plane_strain, keys);
    };
    const FosRunResult slab = bracketed_search(ctx, load_verification_case(ctx), "slab");
    const Ensemble spread = plane_strain_ensemble(
        ctx, plane({"solver.f_bar=true", "solver.f_bar_out_of_plane=true"}), "plane_strain");
    const FosRunResult in_plane =
        bracketed_search(ctx, plane({"solver.f_bar=true"}), "plane_strain_in_plane");
    const FosRunResult slab_plain = bracketed_search(
        ctx, load_verification_case(ctx, {"solver.f_bar=false"}), "slab_without_f_bar");
    const Ensemble plain =
        plane_strain_ensemble(ctx, plane({"solver.f_bar=false"}), "plane_strain_without_f_bar");
    const auto note = [](const FosRunResult& r, const Ensemble& e) {
      return fmt::format("slab bracket [{:.4f}, {:.4f}]; {}", r.fos.lower, r.fos.upper, e.spread());
    };
    return std::vector<Check>{
        relative_check("slab factor of safety against plane strain, without F-bar",
                       slab_plain.fos.value(), plain.nearest(slab_plain.fos.value()), 0.01,
                       note(slab_plain, plain)),
        relative_check("slab factor of safety with F-bar against plane strain's out-of-plane "
                       "F-bar",
                       slab.fos.value(), spread.nearest(slab.fos.value()), 0.01,
                       note(slab, spread)),
        report_only("slab factor of safety with F-bar over plane strain's default F-bar",
                    slab.fos.value() / in_plane.fos.value(),
                    fmt::format("{:.4f} / {:.4f}: the default keeps dF33 = 1 and relieves "
                                "isochoric flow better",
                                slab.fos.value(), in_plane.fos.value())),
        report_only("slab search wall time [s]", slab.wall_seconds,
                    fmt::format("{} trials, {} Newton iterations", slab.fos.trials.size(),
                                slab.newton_iterations))};
  };
  return vc;
}

// A slope of finite width between rough end walls (verification/slope_3d_end_walls.yaml, full
// tier): the Griffiths & Lane section over W = 2 H, half of it modelled (a fixed wall at z = 0,
// the symmetry plane at z = W / 2 on rollers). The reference for the end walls' effect is the
// same 3D model with a roller at z = 0 too (plane strain at the same h, so the ratio of the two
// factors, the rise, cancels the discretisation's own offset), and two independent truths:
//  * End walls only add resistance: the rise exceeds 1 (Cavounidis 1987, Geotechnique 37(2);
//    Griffiths & Marquez 2007, Geotechnique 57(6), find the same by strength reduction). The
//    bound is 1.025, twice the two brackets' combined half-width (1.2 % each), so that a run
//    without the end effect fails it.
//  * The rise by 3D limit equilibrium: Bishop's method extended to columns (Hungr 1987) on the
//    least-factor surface of revolution, over the cylinder with end planes and the surfaces that
//    curve away from the walls (slope_limit_equilibrium.hpp), the end planes' stress K0 sigma_v,
//    K0 = nu / (1 - nu) (gravity between fixed walls), over Bishop's plane-strain circle. It is
//    1.0955 (1.5063 / 1.3749), a profile of exponent 4 longer than the width (L = 25.4 m) that
//    leaves small end planes on the walls; K = 0 and K = 1 give 1.0846 and 1.0976. The cylinder
//    alone gave 1.149 (1.096 to 1.211 over K): curving away from the walls sheds most of their
//    resistance, and the cylinder overstates the end effect by 5 %. Tolerance 4 %, the sum of
//    the rise's search resolution (the brackets' combined 1.2 %), the reference's spread over K
//    in [0, 1] (1.2 %) and Bishop's own offset in plane strain against the finite-element
//    strength reduction (1.374 against 1.4, 1.8 %).
// Measured at h = 1 m (17 600 points, 6 700 unknowns, GMRES with MueLu, one thread, the
// stiffness criterion): walls 1.5688 (bracket [1.5500, 1.5875], 6 trials, 386 Newton
// iterations, 1365 s of CPU), rollers 1.4563 ([1.4375, 1.4750], 6 trials, 206 iterations,
// 559 s): a rise of 1.077, -1.7 % from 1.0955 (before the stiffness criterion: 1.6062 over
// 1.4937, 1.075). h = 1 m is coarse in the factors themselves, not in their ratio.
VerificationCase slope_3d_end_walls() {
  VerificationCase vc;
  vc.name = "slope_3d_end_walls";
  vc.description = "The Griffiths & Lane slope of width W = 2 H between rough end walls: the "
                   "3D factor of safety over the same model's plane-strain factor (rollers), "
                   "against 1 and against 3D limit equilibrium.";
  vc.tiers = {"full"};
  vc.run = [](const VerificationContext& ctx) {
    const CaseSpec spec = load_verification_case(ctx);
    const FosRunResult walls = bracketed_search(ctx, spec, "end_walls");
    const FosRunResult rollers =
        bracketed_search(ctx, load_verification_case(ctx, {"boundaries.z_min=roller"}), "rollers");
    const SlopeSection section = griffiths_lane_section(spec);
    const double width = 2 * spec.grid.extent.z(); // the model is half of the width
    const double nu = spec.materials.front().poisson_ratio;
    const double k0 = nu / (1 - nu);
    const double bishop_2d = critical_circle(section, 0, 0).factor;
    const SlipSurface bishop_3d = critical_surface(section, width, k0, {2, 4, 10});
    const double cylinder_3d = critical_circle(section, width, k0).factor;
    const double rise = walls.fos.value() / rollers.fos.value();
    return std::vector<Check>{
        at_least_check("end-wall rise of the factor of safety", rise, 1.025,
                       fmt::format("{:.4f} / {:.4f}; end walls only add resistance",
                                   walls.fos.value(), rollers.fos.value())),
        relative_check(
            "end-wall rise against 3D limit equilibrium", rise, bishop_3d.factor / bishop_2d, 0.04,
            fmt::format("Hungr's 3D Bishop (K0 = {:.3f}): {:.4f} / {:.4f}, exponent {:g}, length "
                        "{:.1f} m; 4 %: search resolution, spread over K, Bishop against FE",
                        k0, bishop_3d.factor, bishop_2d, bishop_3d.exponent, bishop_3d.length)),
        report_only("cylinder with end planes' rise", cylinder_3d / bishop_2d,
                    "Bishop's circle extruded over W with end planes: overstates the end effect"),
        report_only("3D factor of safety", walls.fos.value(),
                    fmt::format("bracket [{:.4f}, {:.4f}], h = {:g} m, W = {:g} m", walls.fos.lower,
                                walls.fos.upper, spec.grid.cell_size, width)),
        report_only("3D search wall time [s]", walls.wall_seconds,
                    fmt::format("{} trials, {} Newton iterations", walls.fos.trials.size(),
                                walls.newton_iterations))};
  };
  return vc;
}

} // namespace talus::verify_cases
