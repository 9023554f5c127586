#pragma once
// Pore water at rest (the case's water section): the hydrostatic pore pressure below a phreatic
// surface, u = gamma_w (y_w(x) - y), and none above it (no suction). y is vertical, x across;
// in 3D the surface is the same polyline extruded along z. Pore pressure is compression
// positive; the total stress of a point is sigma = sigma' - u I (tension positive), where its
// material gives the effective stress sigma' (docs/case-format.md, water).
#include "talus/core/types.hpp"
#include "talus/spec/case_spec.hpp"

#include <algorithm>
#include <array>
#include <optional>
#include <vector>

namespace talus {

class WaterTable {
public:
  explicit WaterTable(const WaterSpec& spec)
      : unit_weight_(spec.unit_weight), surface_(spec.phreatic) {}

  /// The case's water table, or none for a dry case.
  static std::optional<WaterTable> of(const CaseSpec& spec) {
    return spec.water ? std::optional<WaterTable>(WaterTable(*spec.water)) : std::nullopt;
  }

  double unit_weight() const { return unit_weight_; }

  /// The phreatic surface's height above x: linear between its points, level beyond its ends.
  double level(double x) const {
    if (x <= surface_.front()[0])
      return surface_.front()[1];
    if (x >= surface_.back()[0])
      return surface_.back()[1];
    const auto above = std::upper_bound(surface_.begin(), surface_.end(), x,
                                        [](double v, const auto& p) { return v < p[0]; });
    const auto& [x1, y1] = *above;
    const auto& [x0, y0] = *(above - 1);
    return y0 + (y1 - y0) * (x - x0) / (x1 - x0);
  }

  /// u at position x, Pa.
  template <int Dim> double pore_pressure(const Vec<Dim>& x) const {
    return unit_weight_ * std::max(0.0, level(x[0]) - x[1]);
  }

private:
  double unit_weight_;
  std::vector<std::array<double, 2>> surface_;
};

} // namespace talus
