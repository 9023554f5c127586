#include "talus/solver/energies.hpp"

#include <cmath>

namespace talus {

template <int Dim> Energies particle_energies(const Scene<Dim>& scene, bool with_motion) {
  Energies e;
  const auto& P = scene.particles;
  for (std::size_t m = 0; m < scene.materials.size(); ++m)
    e.strain += scene.materials[m]->stored_energy(scene.particles_of_material[m], P.F, P.volume0);
  const Vec<Dim> g = head<Dim>(scene.spec.gravity);
  // Momentum by compensated (Neumaier) summation: its terms cancel (bodies moving apart), and a
  // plain sum of thousands of them rounds by tens of epsilons of sum m|v|, which would hide
  // the solver's own conservation to round-off that the verification checks.
  Vec<Dim> momentum = Vec<Dim>::Zero(), carry = Vec<Dim>::Zero();
  for (std::size_t s = 0; s < P.x.size(); ++s) {
    e.gravity -= P.mass[s] * g.dot(P.x[s]);
    if (with_motion) {
      e.kinetic += 0.5 * P.mass[s] * P.v[s].squaredNorm();
      for (int d = 0; d < Dim; ++d) {
        const double term = P.mass[s] * P.v[s][d];
        const double sum = momentum[d] + term;
        carry[d] += std::abs(momentum[d]) >= std::abs(term) ? (momentum[d] - sum) + term
                                                            : (term - sum) + momentum[d];
        momentum[d] = sum;
      }
    }
  }
  e.momentum = padded<Dim>(momentum + carry);
  return e;
}

template Energies particle_energies<2>(const Scene<2>&, bool);
template Energies particle_energies<3>(const Scene<3>&, bool);

} // namespace talus
