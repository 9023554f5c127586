#pragma once
// Energy and momentum of the material points, for timeseries.csv and the stability checks.
#include "talus/core/scene.hpp"

namespace talus {

struct Energies {
  double kinetic = 0;  ///< J per unit thickness
  double strain = 0;   ///< J per unit thickness
  double gravity = 0;  ///< potential -sum m g.x, J per unit thickness
  Vec2 momentum{0, 0}; ///< kg m/s per unit thickness
};

/// Sums over the points; stored energy one batch per material. `with_motion` adds kinetic
/// energy and momentum (off for quasi-static runs, whose velocities are pseudo-time rates).
Energies particle_energies(const Scene<2>& scene, bool with_motion);

} // namespace talus
