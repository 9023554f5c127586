#pragma once
// Analytical references and error measures shared by the verification cases and by
// `talus bench` (which sweeps the same scenes): one definition of each formula.
#include "talus/core/types.hpp"
#include "talus/io/csv.hpp"
#include "talus/io/results.hpp"

#include <string>
#include <vector>

namespace talus::references {

// The talk's cantilever (verification/cantilever.yaml): L = 8, D = 1, E = 3e5, nu = 0.
constexpr double kBeamLength = 8.0, kBeamDepth = 1.0, kBeamYoung = 3e5,
                 kBeamInertia = kBeamDepth * kBeamDepth * kBeamDepth / 12.0;

/// Timoshenko & Goodier for nu = 0 (no y dependence), tip shear P (positive down):
/// u_y(x) = -P / (6 E I) (D^2 x + (3L - x) x^2).
double cantilever_deflection(double x, double P);

/// Mean displacement of the points of the last column (largest initial x) between the first
/// and the last frame; *tip_x receives that column's initial x.
Vec2 tip_column_displacement(const ResultsReader& results, double* tip_x);

// The axially vibrating bar (verification/vibrating_bar.yaml).
constexpr double kBarLength = 25.0, kBarYoung = 100.0, kBarDensity = 1.0, kBarV0 = 0.01;

/// RMS over the time series of v_cm(t) - v0/(b1 L) cos(w1 (t - dt/2)), relative to the
/// amplitude v0/(b1 L). Explicit MPM is a leapfrog: the velocity after a step of length dt
/// belongs to t - dt/2 (the initial stress is zero, so the start needs no shift).
double vibrating_bar_rms_error(const CsvTable& series, double total_mass);

/// Overrides for n cells along the bar, one cell high, two spare cells beyond the free end.
std::vector<std::string> vibrating_bar_overrides(int n);

} // namespace talus::references
