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
#include "talus/solver/strength_reduction.hpp"

#include <fmt/format.h>

namespace talus::verify_cases {

namespace {

constexpr double kReferenceFactor = 1.4; // Griffiths & Lane (1999), example 1

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
    FosOptions options;
    options.out_dir = ctx.out_dir / "search";
    options.force = true;
    options.threads = ctx.threads;
    const FosRunResult r = run_factor_of_safety(spec, options);
    if (!r.fos.bracketed)
      throw NumericalError("strength reduction found no bracket: " + r.fos.message);
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

} // namespace talus::verify_cases
