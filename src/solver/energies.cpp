#include "talus/solver/energies.hpp"

#include "talus/core/parallel.hpp"

#include <cmath>

namespace talus {

namespace {

/// Neumaier's compensated step: sum += term, with the rounding error kept in carry.
template <int Dim> void compensated_add(Vec<Dim>& sum, Vec<Dim>& carry, const Vec<Dim>& term) {
  for (int d = 0; d < Dim; ++d) {
    const double t = sum[d] + term[d];
    carry[d] +=
        std::abs(sum[d]) >= std::abs(term[d]) ? (sum[d] - t) + term[d] : (term[d] - t) + sum[d];
    sum[d] = t;
  }
}

template <int Dim> struct PointSums {
  double gravity = 0;
  double kinetic = 0;
  Vec<Dim> momentum = Vec<Dim>::Zero();
  Vec<Dim> carry = Vec<Dim>::Zero();
};

} // namespace

template <int Dim> Energies particle_energies(const Scene<Dim>& scene, bool with_motion) {
  Energies e;
  const auto& P = scene.particles;
  for (std::size_t m = 0; m < scene.materials.size(); ++m)
    e.strain += scene.materials[m]->stored_energy(scene.particles_of_material[m], P.F, P.volume0);
  const Vec<Dim> g = head<Dim>(scene.spec.gravity);
  // Momentum by compensated (Neumaier) summation: its terms cancel (bodies moving apart), and a
  // plain sum of thousands of them rounds by tens of epsilons of sum m|v|, which would hide
  // the solver's own conservation to round-off that the verification checks.
  const PointSums<Dim> sums = parallel_reduce(
      P.size(), PointSums<Dim>{},
      [&](PointSums<Dim>& acc, Index begin, Index end) {
        for (auto s = static_cast<std::size_t>(begin); s < static_cast<std::size_t>(end); ++s) {
          acc.gravity -= P.mass[s] * g.dot(P.x[s]);
          if (with_motion) {
            acc.kinetic += 0.5 * P.mass[s] * P.v[s].squaredNorm();
            compensated_add<Dim>(acc.momentum, acc.carry, P.mass[s] * P.v[s]);
          }
        }
      },
      [](PointSums<Dim>& acc, const PointSums<Dim>& block) {
        acc.gravity += block.gravity;
        acc.kinetic += block.kinetic;
        compensated_add<Dim>(acc.momentum, acc.carry, block.momentum);
        acc.carry += block.carry;
      });
  e.gravity = sums.gravity;
  e.kinetic = sums.kinetic;
  e.momentum = padded<Dim>(sums.momentum + sums.carry);
  return e;
}

template Energies particle_energies<2>(const Scene<2>&, bool);
template Energies particle_energies<3>(const Scene<3>&, bool);

} // namespace talus
