#pragma once
// Internal to the scene (src/scene/): what the case's water changes in a new scene. A point
// generated below the phreatic surface weighs its material's saturated density; a geostatic
// initial stress integrates the dry and saturated weights above each point and carries K0 on
// the effective stress; and water standing on a body is refused, for want of the pressure on
// its surface (docs/case-format.md, water).
#include "talus/scene/scene.hpp"
#include "talus/scene/water_table.hpp"

namespace talus {

/// The density of a point of material m generated at x: saturated below the water table.
template <int Dim>
double point_density(const MaterialSpec& m, const std::optional<WaterTable>& water,
                     const Vec<Dim>& x) {
  return water && m.saturated_density && water->pore_pressure<Dim>(x) > 0 ? *m.saturated_density
                                                                          : m.density;
}

/// The geostatic effective stress sigma' of a point at x under a level surface y = surface of
/// material m (K0 on the effective stress), and its pore pressure u; the total stress is
/// sigma' - u I.
template <int Dim>
Mat3 geostatic_effective_stress(const MaterialSpec& m, double k0, double surface, double g,
                                const std::optional<WaterTable>& water, const Vec<Dim>& x,
                                double& u) {
  const double y = x[1];
  const double y_w = water ? water->level(x[0]) : -std::numeric_limits<double>::infinity();
  const double saturated = water ? std::max(0.0, std::min(surface, y_w) - y) : 0.0;
  const double dry = std::max(0.0, surface - y) - saturated;
  const double total = -g * (m.density * dry + m.saturated_density.value_or(m.density) * saturated);
  u = water ? water->pore_pressure<Dim>(x) : 0.0;
  Mat3 sigma = Mat3::Zero();
  sigma(1, 1) = total + u;
  sigma(0, 0) = sigma(2, 2) = k0 * sigma(1, 1);
  return sigma;
}

/// Throws InputError at the water section when the phreatic surface stands above a body's top
/// (a reservoir or ponded water): the pressure of free water on the surface is not applied, so
/// the body would be out of balance with its pore pressure.
template <int Dim> void refuse_free_water(const Scene<Dim>& scene);

} // namespace talus
