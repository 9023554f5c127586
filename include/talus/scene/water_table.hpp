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
#include <utility>
#include <vector>

namespace talus {

class WaterTable {
public:
  explicit WaterTable(const WaterSpec& spec)
      : unit_weight_(spec.unit_weight), surface_(spec.phreatic) {}

  /// The case's water table, or none for a dry case.
  static std::optional<WaterTable> of(const CaseSpec& spec) {
    return spec.water && !spec.water->phreatic.empty()
               ? std::optional<WaterTable>(WaterTable(*spec.water))
               : std::nullopt;
  }

  double unit_weight() const { return unit_weight_; }

  /// The phreatic surface's height above x: linear between its points, level beyond its ends.
  double level(double x) const { return height(segment(x), x); }

  /// u at position x, Pa.
  template <int Dim> double pore_pressure(const Vec<Dim>& x) const {
    return unit_weight_ * std::max(0.0, level(x[0]) - x[1]);
  }

  /// grad u at position x, Pa/m: gamma_w (dy_w/dx, -1) below the surface, zero above it.
  template <int Dim> Vec<Dim> pressure_gradient(const Vec<Dim>& x) const {
    const auto piece = segment(x[0]);
    Vec<Dim> g = Vec<Dim>::Zero();
    if (height(piece, x[0]) > x[1]) {
      g[0] = unit_weight_ * piece.second;
      g[1] = -unit_weight_;
    }
    return g;
  }

private:
  using Point = std::array<double, 2>;
  /// The point the surface's piece above x starts from, and the piece's slope (zero beyond the
  /// polyline's ends).
  std::pair<std::vector<Point>::const_iterator, double> segment(double x) const {
    if (x <= surface_.front()[0])
      return {surface_.begin(), 0.0};
    if (x >= surface_.back()[0])
      return {surface_.end() - 1, 0.0};
    const auto above = std::upper_bound(surface_.begin(), surface_.end(), x,
                                        [](double v, const Point& p) { return v < p[0]; });
    const auto start = above - 1;
    return {start, ((*above)[1] - (*start)[1]) / ((*above)[0] - (*start)[0])};
  }

  /// The surface's height at x on its piece `piece` (from segment(x)).
  static double height(const std::pair<std::vector<Point>::const_iterator, double>& piece,
                       double x) {
    return (*piece.first)[1] + piece.second * (x - (*piece.first)[0]);
  }

  double unit_weight_;
  std::vector<Point> surface_;
};

} // namespace talus
