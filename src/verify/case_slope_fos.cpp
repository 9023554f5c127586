// Factor of safety of Griffiths & Lane's (1999) example 1 by strength reduction
// (verification/slope_fos.yaml: H = 10 m, 2:1, crest 12 m, firm base at the toe, gamma = 20
// kN/m3, c' = 10 kPa, phi' = 20 deg, psi = 0, E = 1e5 kPa, nu = 0.3). The reference FoS = 1.4
// is Griffiths & Lane's finite-element strength reduction, which agrees with Bishop &
// Morgenstern's charts for c'/(gamma H) = 0.05, phi' = 20 deg, D = 1.
//
// Check and why this bound: the 5 % on the reported factor (the midpoint of the final
// bracket). The bracket is 0.02 wide, so the search resolution contributes at most 0.7 % of
// the 5 %; the rest is the discretisation (volumetric locking of isochoric plastic flow, the
// staircase slope face) and the reference's own precision (quoted to two digits). The search
// time and the trials are reported, not bounded (time-based checks
// would depend on the machine); the target is under 60 s on 2 cores. The Newton
// iterations summed over the trials are bounded at 1200, twice the measured 579, so that a
// search that spends its budget on failing trials again (10227 iterations before the crest
// criterion) fails. Measured at
// h = 0.5 m with F-bar: FoS 1.414 (bracket [1.406, 1.422]), 8 trials, 579 Newton iterations
// (at most 12 per attempt, min_dt 1/32; 1006 with 20 and 1/128, same trials and bracket),
// 20.6 s of CPU (36.9 s before) with spinning OpenMP workers; with passive waits (the default
// now) 12.6 s CPU and 12.7 s wall on 2 threads. In the fast tier for that cost. Failure is Newton's
// non-convergence at min_dt or the crest moving more than 0.1 m = H / 100 (the trial stops
// there): Newton's alone depended on its budget (40 iterations, min_dt 1/512: F = 1.5 stood,
// FoS 1.523); with the limit that budget gives the same bracket.
// Without F-bar the same search gives 1.60, 14 % high: volumetric locking.
#include "cases.hpp"
#include "slope_limit_equilibrium.hpp"
#include "talus/io/case_reader.hpp"
#include "talus/solver/strength_reduction.hpp"

#include <fmt/format.h>

#include <cmath>

namespace talus::verify_cases {

namespace {

constexpr double kReferenceFactor = 1.4; // Griffiths & Lane (1999), example 1

FosRunResult search(const VerificationContext& ctx, const CaseSpec& spec, const std::string& name) {
  FosOptions options;
  options.out_dir = ctx.out_dir / name;
  options.force = true;
  options.threads = ctx.threads;
  FosRunResult r = run_factor_of_safety(spec, options);
  if (!r.fos.bracketed)
    throw NumericalError("strength reduction found no bracket: " + r.fos.message);
  return r;
}

// The section of verification/slope_3d_end_walls.yaml for Bishop's method: the prism's
// face from crest (12, 10) to toe (32, 0), its material and gravity.
SlopeSection griffiths_lane_section(const CaseSpec& spec) {
  const MaterialSpec& soil = spec.materials.front();
  SlopeSection s;
  s.surface_x = {12, 32};
  s.surface_y = {10, 0};
  s.base_y = 0;
  s.unit_weight = soil.density * spec.gravity.norm();
  s.cohesion = soil.cohesion;
  s.tan_phi = std::tan(soil.friction_angle * std::acos(-1.0) / 180);
  return s;
}

} // namespace

VerificationCase slope_fos() {
  VerificationCase vc;
  vc.name = "slope_fos";
  vc.description = "Griffiths & Lane (1999) homogeneous 2:1 slope (c' = 10 kPa, phi' = 20 deg, "
                   "psi = 0): factor of safety by strength reduction (c / F, tan phi / F, "
                   "bisection on F; failure: Newton non-convergence or the crest moving more "
                   "than H / 100) against 1.4.";
  vc.tiers = {"fast", "full"};
  vc.run = [](const VerificationContext& ctx) {
    const CaseSpec spec = load_verification_case(ctx);
    const FosRunResult r = search(ctx, spec, "search");
    const std::string bracket = fmt::format("bracket [{:.4f}, {:.4f}], h = {:g} m", r.fos.lower,
                                            r.fos.upper, spec.grid.cell_size);
    return std::vector<Check>{
        relative_check("factor of safety", r.fos.value(), kReferenceFactor, 0.05, bracket),
        report_only("search wall time [s]", r.wall_seconds,
                    fmt::format("{} trials; target < 60 s on 2 cores", r.fos.trials.size())),
        report_only("search CPU time [s]", r.cpu_seconds, "user + system, all threads"),
        at_most_check("Newton iterations", static_cast<double>(r.newton_iterations), 1200.0,
                      "summed over the trials; 2x the measured 579 (1559 with a patient "
                      "budget, 10227 before the crest criterion)")};
  };
  return vc;
}

// Plane-strain equivalence (verification/slope_fos_slab_3d.yaml, full tier: about ten minutes
// of CPU): the same slope as a 3D prism two cells thick between z rollers. The rollers make the
// 3D problem the plane-strain one, so every trial must stand or fail as in 2D and the search
// end in the same bracket: the factor within 1 % of the 2D search's (the bound; the
// bracket is 1.4 % wide, so one trial decided the other way fails it). Measured: 1.4453
// (bracket [1.4375, 1.4531], 8 trials, 617 Newton iterations, 910 s on a loaded 2-core
// machine) against 1.4141: +2.2 %, a known failure whose cause is not settled. Two candidates,
// both measured: (1) F-bar differs by construction: in 3D it spreads a cell's volume change
// over three axes, dF_bar = (J_bar / j)^(1/3) dF, so the slab's dF33 = 1 becomes dF_bar33 != 1,
// while plane-strain F-bar scales the in-plane block by (J_bar / j)^(1/2) and keeps dF33 = 1;
// (2) even without F-bar, at F = 1.5 (near that variant's factor, 1.6), the slab and the plane
// strain agree to 4e-15 m in the elastic first step but drift apart in the plastic ones:
// 5e-7, 6e-5 and 1.8e-3 m of a 0.05 m largest displacement, with w at 3e-16 and sigma_yz at
// 1e-8 Pa: the plastic path near failure amplifies differences at the Newton tolerance. The
// elastic slab is the plane-strain beam to 1e-11 (cantilever_slab_3d).
VerificationCase slope_fos_slab_3d() {
  VerificationCase vc;
  vc.name = "slope_fos_slab_3d";
  vc.description = "The Griffiths & Lane slope as a 3D slab between z rollers: the strength "
                   "reduction search gives the plane-strain factor of safety.";
  vc.tiers = {"full"};
  vc.run = [](const VerificationContext& ctx) {
    const FosRunResult slab = search(ctx, load_verification_case(ctx), "slab");
    const FosRunResult plane = search(
        ctx, read_case_file((verification_dir() / "slope_fos.yaml").string(), {}), "plane_strain");
    return std::vector<Check>{
        known_failure(
            relative_check("slab factor of safety against plane strain", slab.fos.value(),
                           plane.fos.value(), 0.01,
                           fmt::format("slab bracket [{:.4f}, {:.4f}], plane strain [{:.4f}, "
                                       "{:.4f}]",
                                       slab.fos.lower, slab.fos.upper, plane.fos.lower,
                                       plane.fos.upper)),
            "+2.2 % (1.4453 against 1.4141); candidates: 3D F-bar scales the slab's dF33 too, "
            "and without F-bar the plastic path drifts from plane strain near failure"),
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
//  * The rise against Bishop's simplified method on the circle extruded over W and closed by
//    end planes of strength c' + K0 sigma_v tan(phi'), K0 = nu / (1 - nu) (gravity loading
//    between fixed walls), each factor the minimum over circles (slope_limit_equilibrium.hpp).
//    K = 0 and K = 1 move Bishop's rise from 1.149 to 1.096 and 1.211 (-4.6 %, +5.4 %); that
//    spread is the tolerance, 5 %.
// Measured at h = 1 m (17 600 points, 6 700 unknowns, GMRES with MueLu, two threads): walls
// 1.6062 (bracket [1.5875, 1.6250], 6 trials, 632 Newton iterations, 1118 s), rollers 1.4937
// ([1.4750, 1.5125], 6 trials, 549 iterations, 1119 s): a rise of 1.075 against Bishop's
// 1.149, -6.4 %, below even Bishop's K = 0 (1.096): a known failure. Not settled: Bishop's
// cylinder with full-strength end planes overestimates the end effect (the real surface
// curves away from the walls), and h = 1 m is coarse (the 2D search gives 1.414 at h = 0.5 m,
// against which the walls' factor rises by 1.136, -1.2 %).
VerificationCase slope_3d_end_walls() {
  VerificationCase vc;
  vc.name = "slope_3d_end_walls";
  vc.description = "The Griffiths & Lane slope of width W = 2 H between rough end walls: the "
                   "3D factor of safety over the same model's plane-strain factor (rollers), "
                   "against 1 and against Bishop's circle with end planes.";
  vc.tiers = {"full"};
  vc.run = [](const VerificationContext& ctx) {
    const CaseSpec spec = load_verification_case(ctx);
    const FosRunResult walls = search(ctx, spec, "end_walls");
    const FosRunResult rollers =
        search(ctx, load_verification_case(ctx, {"boundaries.z_min=roller"}), "rollers");
    const SlopeSection section = griffiths_lane_section(spec);
    const double width = 2 * spec.grid.extent.z(); // the model is half of the width
    const double nu = spec.materials.front().poisson_ratio;
    const double k0 = nu / (1 - nu);
    const double bishop_2d = critical_circle(section, 0, 0).factor;
    const double bishop_3d = critical_circle(section, width, k0).factor;
    const double rise = walls.fos.value() / rollers.fos.value();
    return std::vector<Check>{
        at_least_check("end-wall rise of the factor of safety", rise, 1.025,
                       fmt::format("{:.4f} / {:.4f}; end walls only add resistance",
                                   walls.fos.value(), rollers.fos.value())),
        known_failure(
            relative_check("end-wall rise against Bishop", rise, bishop_3d / bishop_2d, 0.05,
                           fmt::format("Bishop with end planes (K0 = {:.3f}): {:.4f} / {:.4f}; "
                                       "5 %: Bishop's spread over K in [0, 1]",
                                       k0, bishop_3d, bishop_2d)),
            "-6.4 % (1.075 against 1.149); Bishop's cylinder with end planes may overstate "
            "the end effect, and h = 1 m is coarse"),
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
