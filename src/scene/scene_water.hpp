#pragma once
// Internal to the scene (src/scene/): what the case's water changes in a new scene. A point
// generated below the phreatic surface weighs its material's saturated density, and a
// geostatic initial stress integrates the free water, dry and saturated weights above each
// point and carries K0 on the effective stress (docs/case-format.md, water).
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
/// material m, below any free water standing on it (K0 on the effective stress), and its pore
/// pressure u; the total stress is sigma' - u I.
template <int Dim>
Mat3 geostatic_effective_stress(const MaterialSpec& m, double k0, double surface, double g,
                                const std::optional<WaterTable>& water, const Vec<Dim>& x,
                                double& u) {
  const double y = x[1];
  const double y_w = water ? water->level(x[0]) : -std::numeric_limits<double>::infinity();
  const double saturated = water ? std::max(0.0, std::min(surface, y_w) - y) : 0.0;
  const double dry = std::max(0.0, surface - y) - saturated;
  const double free_water = water ? water->unit_weight() * std::max(0.0, y_w - surface) : 0.0;
  const double total =
      -g * (m.density * dry + m.saturated_density.value_or(m.density) * saturated) - free_water;
  u = water ? water->pore_pressure<Dim>(x) : 0.0;
  Mat3 sigma = Mat3::Zero();
  sigma(1, 1) = total + u;
  sigma(0, 0) = sigma(2, 2) = k0 * sigma(1, 1);
  return sigma;
}

} // namespace talus
