#pragma once
// Energy and momentum of the material points, for timeseries.csv and the stability checks.
#include "talus/scene/scene.hpp"

namespace talus {

/// Energies in J (per unit thickness in 2D), momentum in kg m/s (z = 0 in 2D).
struct Energies {
  double kinetic = 0;
  double strain = 0;
  double gravity = 0; ///< potential -sum m g.x
  Vec3 momentum{0, 0, 0};
};

/// Sums over the points; stored energy one batch per material. `with_motion` adds kinetic
/// energy and momentum (off for quasi-static runs, whose velocities are pseudo-time rates).
template <int Dim> Energies particle_energies(const Scene<Dim>& scene, bool with_motion);

} // namespace talus
