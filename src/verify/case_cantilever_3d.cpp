// The cantilever in 3D (verification/cantilever_3d.yaml): a square section D x D, L/D = 8, the
// root supported as Timoshenko-Goodier's solution is (plane, free to contract laterally,
// pinned on its neutral lines), a shear traction of resultant P on the end face; implicit
// quasi-static, GIMP, 2 x 2 x 2 points per cell; nu = 0 and 0.3 at 2, 4 and 8 cells through the
// depth. Measured tip-column deflection errors against Timoshenko-Goodier ((4 + 5 nu) / 4 shear
// term): nu = 0 -3.33 %, -0.71 %, -0.016 %; nu = 0.3 -4.02 %, -0.89 %, -0.051 %; observed orders
// of the successive changes 1.93 and 1.89 (GIMP displacements converge at second order).
//  * The 8-cell error sits where the discretisation error (about -0.3 % left at 8 cells, from
//    the last change and the order) crosses a model difference of about +0.25 % (the
//    Richardson limit: the root section here cannot warp, T-G's can; the 2D beam at 16 cells
//    shows +0.10 %). Its measured 0.05 % understates both, so the bound is their sum, 0.5 %, and
//    the limit itself is bounded too: within 0.5 % of T-G (measured +0.23 %, +0.26 %).
//  * Observed order in [1.5, 2.5] (theory 2).
//  * A fully clamped root (x_min: fixed) at nu = 0.3, 8 cells, reported: -1.11 % (-0.82 % at 16
//    cells); it restrains the Poisson contraction that T-G leaves free. Run with the clamped
//    root, the nu = 0.3 deflection check fails (tried).
//
// Plane-strain equivalence (verification/cantilever_slab_3d.yaml): the 2D cantilever at 8
// cells and nu = 0.3 as a 3D slab two cells thick between rollers on both z faces. The rollers
// and the mid-plane symmetry make the 3D solution the plane-strain one, so the tip deflections
// must agree to the Newton tolerance (measured 1.3e-11 relative; bounded at 1e-10, 7x: the
// two Newton runs stop at different residuals below the tolerance, 2.5e-11 seen) and the
// points must not move through the thickness (|w| / |v_tip| measured 0; bounded at 1e-12). A z
// face left free (plane stress through the thickness) differs by 9 % and a ghost penalty that
// took the slab's z faces for free boundaries (stabilising every face of the slab) by 1.4e-4:
// both fail (tried).
#include "cases.hpp"
#include "references.hpp"
#include "talus/io/case_reader.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>

namespace talus::verify_cases {

namespace {

struct TipDeflection {
  double error = 0;   ///< against Timoshenko-Goodier at the tip column
  double at_tip = 0;  ///< scaled to x = L, to compare resolutions (tip columns sit at L - h/4)
  double lateral = 0; ///< z displacement over the T-G deflection (0 by symmetry)
};

/// The mean displacement of the tip column of points, and the largest |w| of any point.
Vec3 tip_column(const std::filesystem::path& dir, double* largest_w = nullptr) {
  double x = 0;
  const ResultsReader results(dir / "run.h5");
  if (largest_w) {
    Index rows = 0, cols = 0;
    const auto x0 = results.read(0, "position", &rows, &cols);
    const auto x1 = results.read(results.frame_count() - 1, "position", &rows, &cols);
    *largest_w = 0;
    for (Index p = 0; p < rows; ++p) {
      const auto z = static_cast<std::size_t>(cols * p + 2);
      *largest_w = std::max(*largest_w, std::abs(x1[z] - x0[z]));
    }
  }
  return references::tip_column_displacement(results, &x);
}

TipDeflection tip_deflection(const VerificationContext& ctx, int cells, double nu,
                             const std::string& label, std::vector<std::string> overrides = {}) {
  overrides.push_back(fmt::format("grid.cell_size={:.17g}", references::kBeamDepth / cells));
  overrides.push_back(fmt::format("materials.beam.poisson_ratio={:g}", nu));
  const auto dir = ctx.out_dir / fmt::format("{}nu{:g}_{}cells", label, nu, cells);
  run_quiet(load_verification_case(ctx, overrides), dir, ctx.threads);
  double x = 0;
  const Vec3 u = references::tip_column_displacement(ResultsReader(dir / "run.h5"), &x);
  const double reference = references::cantilever_deflection(x, 1.0, nu);
  return {u.y() / reference - 1.0,
          u.y() / reference * references::cantilever_deflection(references::kBeamLength, 1.0, nu),
          u.z() / reference};
}

} // namespace

VerificationCase cantilever_3d() {
  VerificationCase vc;
  vc.name = "cantilever_3d";
  vc.distributable = true;
  vc.description = "The cantilever in 3D, square section, L/D = 8: the tip deflection against "
                   "Timoshenko-Goodier for nu = 0 and 0.3 at 2, 4 and 8 cells through the depth "
                   "with the observed order (GIMP, implicit).";
  vc.tiers = {"fast", "full"};
  vc.run = [](const VerificationContext& ctx) {
    std::vector<Check> checks;
    const int depth_cells[] = {2, 4, 8};
    for (const double nu : {0.0, 0.3}) {
      std::vector<TipDeflection> d;
      for (const int n : depth_cells) {
        d.push_back(tip_deflection(ctx, n, nu, ""));
        const std::string lateral = fmt::format("lateral/deflection {:.2g}", d.back().lateral);
        checks.push_back(
            n == 8 ? absolute_check(fmt::format("tip deflection error, nu = {:g}, 8 cells", nu),
                                    d.back().error, 0.0, 0.005, "Timoshenko-Goodier; " + lateral)
                   : report_only(fmt::format("tip deflection error, nu = {:g}, {} cells", nu, n),
                                 d.back().error, lateral));
      }
      const double coarse = std::abs(d[1].at_tip - d[0].at_tip);
      const double fine = std::abs(d[2].at_tip - d[1].at_tip);
      const double order = observed_order(coarse, fine);
      checks.push_back(within_check(fmt::format("observed order, nu = {:g}, 2->4->8", nu), order,
                                    1.5, 2.5, "self-convergence; theory 2"));
      const double limit = d[2].at_tip + (d[2].at_tip - d[1].at_tip) / (std::exp2(order) - 1.0);
      const double tg = references::cantilever_deflection(references::kBeamLength, 1.0, nu);
      checks.push_back(absolute_check(fmt::format("Richardson limit error, nu = {:g}", nu),
                                      limit / tg - 1.0, 0.0, 0.005,
                                      "model difference: the root section cannot warp"));
    }
    const TipDeflection clamped =
        tip_deflection(ctx, 8, 0.3, "clamped_", {"boundaries.x_min=fixed"});
    checks.push_back(report_only("clamped root: tip deflection error, nu = 0.3, 8 cells",
                                 clamped.error, "the clamp restrains the Poisson contraction"));
    return checks;
  };
  return vc;
}

VerificationCase cantilever_slab_3d() {
  VerificationCase vc;
  vc.name = "cantilever_slab_3d";
  vc.description = "Plane-strain equivalence: the 2D cantilever (nu = 0.3, 8 cells) as a 3D slab "
                   "between rollers on both z faces gives the plane-strain deflection.";
  vc.tiers = {"fast", "full"};
  vc.run = [](const VerificationContext& ctx) {
    const auto slab_dir = ctx.out_dir / "slab";
    run_quiet(load_verification_case(ctx, {}), slab_dir, ctx.threads);
    const auto plane_dir = ctx.out_dir / "plane_strain";
    run_quiet(read_case_file((verification_dir() / "cantilever.yaml").string(),
                             {"materials.beam.poisson_ratio=0.3"}),
              plane_dir, ctx.threads);
    double largest_w = 0;
    const Vec3 slab = tip_column(slab_dir, &largest_w);
    const Vec3 plane = tip_column(plane_dir);
    std::vector<Check> checks;
    checks.push_back(relative_check("slab tip deflection against plane strain", slab.y(), plane.y(),
                                    1e-10, "Newton tolerance; measured 1.3e-11"));
    checks.push_back(at_most_check("largest |w| / |v_tip|", largest_w / std::abs(plane.y()), 1e-12,
                                   "rollers and mid-plane symmetry: w = 0"));
    return checks;
  };
  return vc;
}

} // namespace talus::verify_cases
