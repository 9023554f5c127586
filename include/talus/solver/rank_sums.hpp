#pragma once
// What the ranks' shares of a step add up to: each value summed over the ranks in rank order,
// so every rank holds the same bits (on one rank, the value itself).
#include "talus/parallel/communicator.hpp"
#include "talus/scene/scene.hpp"
#include "talus/solver/energies.hpp"

#include <algorithm>
#include <span>
#include <vector>

namespace talus {

inline Energies summed_over_ranks(const Energies& e, const Communicator& comm) {
  const double mine[] = {e.kinetic,      e.strain,       e.gravity,
                         e.momentum.x(), e.momentum.y(), e.momentum.z()};
  const std::vector<double> t = comm.sum(mine);
  return {t[0], t[1], t[2], Vec3(t[3], t[4], t[5])};
}

/// Forces (reactions) summed element by element.
inline std::vector<Vec3> summed_over_ranks(std::span<const Vec3> forces, const Communicator& comm) {
  std::vector<double> flat;
  flat.reserve(3 * forces.size());
  for (const Vec3& f : forces)
    flat.insert(flat.end(), f.data(), f.data() + 3);
  const std::vector<double> t = comm.sum(flat);
  std::vector<Vec3> out(forces.size());
  for (std::size_t k = 0; k < out.size(); ++k)
    out[k] = Vec3(t[3 * k], t[3 * k + 1], t[3 * k + 2]);
  return out;
}

inline FaceReactions summed_over_ranks(const FaceReactions& reactions, const Communicator& comm) {
  const std::vector<Vec3> t = summed_over_ranks(std::span<const Vec3>(reactions), comm);
  FaceReactions out;
  std::copy(t.begin(), t.end(), out.begin());
  return out;
}

} // namespace talus
