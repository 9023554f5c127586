#pragma once
// Factories of the verification cases (one file each) and helpers they share.
#include "talus/io/results.hpp"
#include "talus/solver/run.hpp"
#include "talus/solver/strength_reduction.hpp"
#include "talus/verify/verification.hpp"

namespace talus::verify_cases {

VerificationCase vibrating_bar();
VerificationCase vibrating_bar_implicit();
VerificationCase vibrating_bar_3d();
VerificationCase vibrating_bar_implicit_3d();
VerificationCase vibrating_bar_shapes();
VerificationCase colliding_discs();
VerificationCase colliding_discs_shapes();
VerificationCase rigid_translation();
VerificationCase rigid_translation_3d();
VerificationCase colliding_spheres();
VerificationCase rigid_rotation();
VerificationCase rigid_rotation_3d();
VerificationCase cantilever();
VerificationCase cantilever_shapes();
VerificationCase cantilever_3d();
VerificationCase cantilever_slab_3d();
VerificationCase self_weight_column();
VerificationCase self_weight_column_3d();
VerificationCase submerged_column();
VerificationCase terzaghi();
VerificationCase infinite_slope_seepage();
VerificationCase mandel();
VerificationCase column_large_compression();
VerificationCase single_element();
VerificationCase single_element_3d();
VerificationCase grashof();
VerificationCase strip_footing();
VerificationCase strip_footing_frictional();
VerificationCase axisymmetric_cylinder();
VerificationCase lame_cylinder();
VerificationCase breathing_cylinder();
VerificationCase circular_footing();
VerificationCase slope_fos();
VerificationCase slope_drawdown();
VerificationCase embankment_consolidation();
VerificationCase slope_fos_refinement();
VerificationCase slope_fos_refinement_c5_phi30();
VerificationCase slope_fos_refinement_steep();
VerificationCase slope_fos_slab_3d();
VerificationCase slope_3d_end_walls();
// The stability tier (`talus verify --tier stability`).
VerificationCase stability_explicit_cfl();
VerificationCase stability_implicit_dt();
VerificationCase stability_rotation();
VerificationCase stability_distortion();
VerificationCase stability_recovery();
VerificationCase stability_cell_crossing();
VerificationCase stability_tiny_mass();
VerificationCase stability_stiffness_contrast();
VerificationCase stability_incompressibility();
VerificationCase stability_perturbed();

/// Runs a verification scene quietly into `dir`, throwing if it did not complete.
RunResult run_quiet(const CaseSpec& spec, const std::filesystem::path& dir, int threads);

/// Searches the factor of safety of `spec` into ctx.out_dir / name, throwing if no bracket was
/// found.
FosRunResult bracketed_search(const VerificationContext& ctx, const CaseSpec& spec,
                              const std::string& name);

/// A frame's points as the consolidation cases read them: reference and current positions
/// (`dims` per point), volumes and pore pressures.
struct PoreFrame {
  std::vector<double> x0, x, volume, p;
  std::size_t dims = 0;
};
PoreFrame read_pore_frame(const ResultsReader& results, Index frame);

/// Runs the case's scene with `overrides` into ctx.out_dir / run and returns the Cauchy stress
/// of its first point in the last frame (the single-element cases, whose points all agree).
Mat3 final_point_stress(const VerificationContext& ctx, const std::string& run,
                        const std::vector<std::string>& overrides);

} // namespace talus::verify_cases
