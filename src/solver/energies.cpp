#include "talus/solver/energies.hpp"

namespace talus {

template <int Dim> Energies particle_energies(const Scene<Dim>& scene, bool with_motion) {
  Energies e;
  const auto& P = scene.particles;
  for (std::size_t m = 0; m < scene.materials.size(); ++m)
    e.strain += scene.materials[m]->stored_energy(scene.particles_of_material[m], P.F, P.volume0);
  const Vec<Dim> g = head<Dim>(scene.spec.gravity);
  Vec<Dim> momentum = Vec<Dim>::Zero();
  for (std::size_t s = 0; s < P.x.size(); ++s) {
    e.gravity -= P.mass[s] * g.dot(P.x[s]);
    if (with_motion) {
      e.kinetic += 0.5 * P.mass[s] * P.v[s].squaredNorm();
      momentum += P.mass[s] * P.v[s];
    }
  }
  e.momentum = padded<Dim>(momentum);
  return e;
}

template Energies particle_energies<2>(const Scene<2>&, bool);
template Energies particle_energies<3>(const Scene<3>&, bool);

} // namespace talus
