#include "scene_water.hpp"

#include "talus/core/errors.hpp"

#include <cmath>
#include <fmt/format.h>
#include <map>
#include <utility>

namespace talus {

template <int Dim> void refuse_free_water(const Scene<Dim>& scene) {
  const std::optional<WaterTable> water = WaterTable::of(scene.spec);
  if (!water)
    return;
  // The top of each body in every column of points (a cell wide), and where it is.
  const auto& P = scene.particles;
  const double h = scene.grid.cell_size();
  std::map<std::pair<int, std::pair<long, long>>, Vec<Dim>> top;
  for (std::size_t s = 0; s < P.x.size(); ++s) {
    const Vec<Dim>& x = P.x[s];
    const auto key =
        std::pair{P.body[s], std::pair{std::lround(std::floor(x[0] / h)),
                                       Dim == 3 ? std::lround(std::floor(x[Dim - 1] / h)) : 0L}};
    const auto [at, inserted] = top.emplace(key, x);
    if (!inserted && x[1] > at->second[1])
      at->second = x;
  }
  for (const auto& [key, x] : top) {
    const double above = water->level(x[0]) - x[1];
    // The top point sits up to half a point spacing below the surface it stands for.
    if (above > 0.5 * h)
      throw InputError(scene.spec.water->where,
                       fmt::format("the phreatic surface stands {:.3g} m above body '{}' at x = "
                                   "{:.4g} (its top point is at y = {:.4g}): water standing on a "
                                   "body (a reservoir, ponding) needs its pressure on the body's "
                                   "surface, which Talus does not apply yet; lower the water to "
                                   "the body's surface",
                                   above,
                                   scene.spec.bodies[static_cast<std::size_t>(key.first)].name,
                                   x[0], x[1]));
  }
}

template void refuse_free_water<2>(const Scene<2>&);
template void refuse_free_water<3>(const Scene<3>&);

} // namespace talus
