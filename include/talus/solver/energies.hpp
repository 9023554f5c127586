#pragma once
// Energy and momentum of the material points, for timeseries.csv and the stability checks.
#include "talus/core/scene.hpp"

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

/// The ranks' energies of a distributed run added up (in rank order, the same on every rank).
inline Energies summed_over_ranks(const Energies& e, const Communicator& comm) {
  const double mine[] = {e.kinetic,      e.strain,       e.gravity,
                         e.momentum.x(), e.momentum.y(), e.momentum.z()};
  const std::vector<double> t = comm.sum(mine);
  return {t[0], t[1], t[2], Vec3(t[3], t[4], t[5])};
}

} // namespace talus
