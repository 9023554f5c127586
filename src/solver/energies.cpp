#include "talus/solver/energies.hpp"

namespace talus {

Energies particle_energies(const Scene<2>& scene, bool with_motion) {
  Energies e;
  const auto& P = scene.particles;
  for (std::size_t m = 0; m < scene.materials.size(); ++m)
    e.strain += scene.materials[m]->stored_energy(scene.particles_of_material[m], P.F, P.volume0);
  const Vec2 g = scene.spec.gravity;
  for (std::size_t s = 0; s < P.x.size(); ++s) {
    e.gravity -= P.mass[s] * g.dot(P.x[s]);
    if (with_motion) {
      e.kinetic += 0.5 * P.mass[s] * P.v[s].squaredNorm();
      e.momentum += P.mass[s] * P.v[s];
    }
  }
  return e;
}

} // namespace talus
