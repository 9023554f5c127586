#pragma once
// Analytical references and error measures shared by the verification cases and by
// `talus bench` (which sweeps the same scenes): one definition of each formula.
#include "talus/core/types.hpp"
#include "talus/io/csv.hpp"
#include "talus/io/results.hpp"

#include <functional>
#include <string>
#include <vector>

namespace talus::references {

/// int_a^b f by composite Simpson's rule on `intervals` (even) intervals.
double simpson(const std::function<double(double)>& f, double a, double b, int intervals = 2000);

// The talk's cantilever (verification/cantilever.yaml): L = 8, D = 1, E = 3e5, nu = 0.
constexpr double kBeamLength = 8.0, kBeamDepth = 1.0, kBeamYoung = 3e5,
                 kBeamInertia = kBeamDepth * kBeamDepth * kBeamDepth / 12.0;

/// Timoshenko & Goodier's cantilever (plane stress) on its axis y = 0, tip shear P (positive
/// down): u_y(x) = -P / (6 E I) ((4 + 5 nu) D^2 x / 4 + (3L - x) x^2). At the tip (x = L) the
/// term 3 nu y^2 (L - x) that varies over the depth vanishes, so this is also the mean over the
/// end section; for nu = 0 the deflection of every fibre. Per unit thickness, and for a beam
/// of square section D x D with P the resultant.
double cantilever_deflection(double x, double P, double nu = 0.0);

/// Mean displacement of the points of the last column (largest initial x) between the first
/// and the last frame (z = 0 in 2D); *tip_x receives that column's initial x.
Vec3 tip_column_displacement(const ResultsReader& results, double* tip_x);

/// The elastica of the cantilever under a dead tip load P L^2 / (E I) = alpha (inextensible,
/// shear-rigid): theta'' = -alpha cos(theta) on s in [0, 1], theta(0) = 0, theta'(1) = 0,
/// solved by shooting with RK4 (4000 steps, bisection to 1e-10 on theta'(0)). Displacements of
/// the point at arclength s (rounded to a multiple of 1/4000) over L.
struct Elastica {
  double u_over_L; ///< horizontal shortening
  double v_over_L; ///< vertical deflection
};
Elastica elastica(double alpha, double s);

/// The large-deflection beam: the talk's cantilever made twice as slender (L = 8, D = 0.5,
/// L/D = 16), because the elastica is an inextensible, shear-rigid line: at L/D = 8 and
/// alpha = 2 the continuum beam is 2.2 % softer than the elastica from shear flexibility and the
/// 12 % fibre strain alone (measured; the Reissner beam with shear explains half of it), at
/// L/D = 16 both effects are four times smaller.
constexpr double kSlenderBeamDepth = 0.5;

/// Overrides that turn verification/cantilever.yaml into the large-deflection beam: the
/// slender section, Hencky material, a dead tip load P = alpha E I / L^2 reached in `steps`
/// equal load steps, `depth_cells` cells through the depth, a grid deep enough for the bent
/// beam, and only the first and last frames written.
std::vector<std::string> large_deflection_overrides(double alpha, int steps, int depth_cells);

/// max(|u/u_ref - 1|, |v/v_ref - 1|) of the tip column of a large-deflection run against the
/// elastica at that column's arclength.
double large_deflection_error(const ResultsReader& results, double alpha);

// The soft column compressed by its own weight (verification/column_large_compression.yaml):
// H = 1 m, rho0 = 1000 kg/m^3, g = 10 m/s^2, nu = 0.3, Hencky, rollers on the sides and base.
constexpr double kColumnHeight = 1.0, kColumnDensity = 1000.0, kColumnGravity = 10.0,
                 kColumnPoisson = 0.3;

/// Overrides for n cells over the height (a column four cells wide) and Young's modulus from
/// rho g H / E = ratio.
std::vector<std::string> compressed_column_overrides(int n, double ratio);

/// The errors of a compressed-column run against the exact one-dimensional solution in the
/// initial height Y: sigma_yy = -rho0 g (H - Y), the stretch lambda from
/// M ln(lambda) / lambda = sigma_yy (M = lambda_L + 2 mu), u(Y) = int_0^Y (lambda - 1) dY'.
struct ColumnErrors {
  double raw = 0, smoothed = 0; ///< volume-weighted relative L2 errors of sigma_yy
  double top = 0;               ///< the top row's displacement, relative error (signed)
};
ColumnErrors compressed_column_errors(const ResultsReader& results, double ratio);

// The axially vibrating bar (verification/vibrating_bar.yaml).
constexpr double kBarLength = 25.0, kBarYoung = 100.0, kBarDensity = 1.0, kBarV0 = 0.01;

/// RMS over the time series of v_cm(t) - v0/(b1 L) cos(w1 (t - dt/2)), relative to the
/// amplitude v0/(b1 L). Explicit MPM is a leapfrog: the velocity after a step of length dt
/// belongs to t - dt/2 (the initial stress is zero, so the start needs no shift).
double vibrating_bar_rms_error(const CsvTable& series, double total_mass);

/// Overrides for n cells along the bar, `height_cells` cells high (and, in 3D, as many deep),
/// two spare cells beyond the free end.
std::vector<std::string> vibrating_bar_overrides(int n, int dimension = 2, int height_cells = 1);

} // namespace talus::references
