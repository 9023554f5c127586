#include "slope_limit_equilibrium.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace talus::verify_cases {

namespace {

double surface_height(const SlopeSection& s, double x) {
  const auto& xs = s.surface_x;
  if (x <= xs.front())
    return s.surface_y.front();
  if (x >= xs.back())
    return s.surface_y.back();
  const auto k = static_cast<std::size_t>(std::upper_bound(xs.begin(), xs.end(), x) - xs.begin());
  const double t = (x - xs[k - 1]) / (xs[k] - xs[k - 1]);
  return s.surface_y[k - 1] + t * (s.surface_y[k] - s.surface_y[k - 1]);
}

// Slices over the chord of the circle and sub-layers of each slice for the end planes: fine
// enough that halving both changes the factors by at most 0.15 % and the 3D / 2D ratio by at
// most 0.2 % (measured on Griffiths & Lane's slope), below the method's own error.
constexpr int kSlices = 200;
constexpr int kEndLayers = 16;

} // namespace

SlipCircle bishop_circle(const SlopeSection& s, double centre_x, double centre_y, double radius,
                         double width, double end_stress_ratio) {
  SlipCircle c{0, centre_x, centre_y, radius};
  if (radius <= 0 || centre_y - radius < s.base_y - 1e-12)
    return c;
  struct Slice {
    double x, base, height;
  };
  std::vector<Slice> slices;
  const double b = 2 * radius / kSlices;
  double moment = 0; // of the weight about the centre, per unit width (+: slides towards +x)
  for (int i = 0; i < kSlices; ++i) {
    const double x = centre_x - radius + (i + 0.5) * b;
    const double base =
        centre_y - std::sqrt(std::max(0.0, radius * radius - (x - centre_x) * (x - centre_x)));
    const double h = surface_height(s, x) - base;
    if (h > 0) {
      slices.push_back({x, base, h});
      moment += s.unit_weight * h * b * (centre_x - x);
    }
  }
  if (slices.size() < 5 || moment == 0)
    return c;
  const double direction = moment > 0 ? 1.0 : -1.0;
  const double driving = std::abs(moment);

  // The end planes' resisting moment at full strength: the shear stress acts along the circle
  // of rotation through each point, so its arm is the distance to the centre.
  double end_moment = 0;
  if (width > 0) {
    for (const Slice& sl : slices) {
      const double dy = sl.height / kEndLayers;
      for (int j = 0; j < kEndLayers; ++j) {
        const double y = sl.base + (j + 0.5) * dy;
        const double sigma_v = s.unit_weight * (sl.base + sl.height - y);
        const double strength = s.cohesion + end_stress_ratio * sigma_v * s.tan_phi;
        end_moment += strength * std::hypot(sl.x - centre_x, y - centre_y) * b * dy;
      }
    }
  }

  // Bishop's fixed point F = R sum (c b + W tan phi) / m_alpha / sum W (x_c - x), with
  // m_alpha = cos(alpha) + sin(alpha) tan(phi) / F; m_alpha is kept above 0.2 near the toe
  // (the usual guard against its spurious zero).
  double factor = 1.5;
  for (int iteration = 0; iteration < 100; ++iteration) {
    double resisting = 0;
    for (const Slice& sl : slices) {
      const double sin_a = direction * (centre_x - sl.x) / radius;
      const double cos_a = std::sqrt(std::max(1e-12, 1 - sin_a * sin_a));
      const double m_alpha = std::max(0.2, cos_a + sin_a * s.tan_phi / factor);
      resisting += (s.cohesion * b + s.unit_weight * sl.height * b * s.tan_phi) / m_alpha;
    }
    resisting *= radius;
    const double next =
        width > 0 ? (width * resisting + 2 * end_moment) / (width * driving) : resisting / driving;
    const bool settled = std::abs(next - factor) < 1e-10 * next;
    factor = next;
    if (settled)
      break;
  }
  c.factor = factor;
  return c;
}

SlipCircle critical_circle(const SlopeSection& s, double width, double end_stress_ratio) {
  const double x0 = s.surface_x.front(), x1 = s.surface_x.back();
  const double top = *std::max_element(s.surface_y.begin(), s.surface_y.end());
  const double height = top - s.base_y;
  // Circles by centre and clearance above the base (radius = centre_y - base_y - clearance),
  // so that the search can slide along the circles tangent to the base, where the critical
  // one of a slope on a firm base usually lies.
  SlipCircle best{};
  double best_clearance = 0;
  auto consider = [&](double cx, double cy, double clearance) {
    if (clearance < 0)
      return;
    const SlipCircle c =
        bishop_circle(s, cx, cy, cy - s.base_y - clearance, width, end_stress_ratio);
    if (c.factor > 0 && (best.factor == 0 || c.factor < best.factor)) {
      best = c;
      best_clearance = clearance;
    }
  };
  // A grid of centres above the section and clearances up to the slope's height...
  for (int i = 0; i <= 32; ++i) {
    for (int j = 1; j <= 24; ++j) {
      const double cx = x0 + (x1 - x0) * i / 32.0;
      const double cy = top + 3 * height * j / 24.0;
      for (int k = 0; k < 16; ++k)
        consider(cx, cy, height * k / 16.0);
    }
  }
  // ...then a pattern search in (centre, clearance) down to a step of H / 1000.
  for (double step = height / 16; step > height / 1000;) {
    const SlipCircle start = best;
    const double clearance = best_clearance;
    const std::array<std::array<double, 3>, 6> moves{
        {{step, 0, 0}, {-step, 0, 0}, {0, step, 0}, {0, -step, 0}, {0, 0, step}, {0, 0, -step}}};
    for (const auto& m : moves)
      consider(start.centre_x + m[0], start.centre_y + m[1], clearance + m[2]);
    if (best.factor >= start.factor)
      step /= 2;
  }
  return best;
}

} // namespace talus::verify_cases
