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

// The effective vertical stress at depth in the column at x, from y up to the ground: its weight
// less the water's buoyancy below the water level. With the same level inside the slope and in
// front of it (water at rest), this is the total weight, the water on the face and the pore
// pressure on the slip surface taken together.
double effective_weight(const SlopeSection& s, double ground, double y) {
  const double submerged = std::max(0.0, std::min(ground, s.water_level) - y);
  return s.unit_weight * (ground - y) - s.water_unit_weight * submerged;
}

// Columns over the chord of each circle, sub-layers of each for the end planes, and strips over
// the half-width for surfaces of revolution: fine enough that halving the first two changes the
// factors by at most 0.15 % and the 3D / 2D ratio by at most 0.2 %, and halving or doubling the
// strips the least factor over the curved surfaces by at most 0.1 % (measured on Griffiths &
// Lane's slope at W = 2 H; 32 strips missed the steep flanks by 1 %), below the method's own
// error.
constexpr int kSlices = 200;
constexpr int kEndLayers = 16;
constexpr int kStrips = 128;

// One column of the slip mass: its base's downhill slope (cx - x) / r before the sliding
// direction is known, the vertical component n_y of its base normal, the shear's arm about the
// axis (the local radius), its base area and its weight.
struct Column {
  double downhill, normal_y, arm, area, weight;
};

// The section at one z: the circle of radius r about the axis, over a strip dz wide, whose base
// is steeper in z by sqrt(1 + r'(z)^2). Appends its columns and returns the weight's moment
// about the axis (+: the mass rotates counter-clockwise, sliding towards +x).
double add_columns(const SlopeSection& s, double cx, double cy, double r, double dz,
                   double steepness, std::vector<Column>& columns) {
  const double b = 2 * r / kSlices;
  double moment = 0;
  for (int i = 0; i < kSlices; ++i) {
    const double x = cx - r + (i + 0.5) * b;
    const double depth = std::sqrt(std::max(0.0, r * r - (x - cx) * (x - cx)));
    const double ground = surface_height(s, x);
    if (ground <= cy - depth)
      continue;
    const double weight = effective_weight(s, ground, cy - depth) * b * dz;
    const double normal_y = depth / r / steepness;
    columns.push_back({(cx - x) / r, normal_y, r, b * dz / normal_y, weight});
    moment += weight * (cx - x);
  }
  return moment;
}

// The full-strength moment of one end plane: the part of a wall inside the circle of radius r
// and below the ground. The shear acts along the circle of rotation through each point, so its
// arm is the distance to the axis.
double end_plane_moment(const SlopeSection& s, double cx, double cy, double r,
                        double end_stress_ratio) {
  const double b = 2 * r / kSlices;
  double moment = 0;
  for (int i = 0; i < kSlices; ++i) {
    const double x = cx - r + (i + 0.5) * b;
    const double ground = surface_height(s, x);
    const double base = cy - std::sqrt(std::max(0.0, r * r - (x - cx) * (x - cx)));
    const double dy = (ground - base) / kEndLayers;
    if (dy <= 0)
      continue;
    for (int j = 0; j < kEndLayers; ++j) {
      const double y = base + (j + 0.5) * dy;
      const double strength =
          s.cohesion + end_stress_ratio * effective_weight(s, ground, y) * s.tan_phi;
      moment += strength * std::hypot(x - cx, y - cy) * b * dy;
    }
  }
  return moment;
}

// Bishop's fixed point F = (sum r (c' A + N tan(phi')) + M_end) / M_weight: moment equilibrium
// about the axis (the normal forces pass through it), each column's normal force from its
// vertical equilibrium N n_y + S sin(alpha) = W with S = (c' A + N tan(phi')) / F:
// N = (W - c' A sin(alpha) / F) / m_alpha, m_alpha = n_y + sin(alpha) tan(phi') / F. m_alpha
// is kept above 0.2 near the toe (the usual guard against its spurious zero), and N at zero or
// above: on the steep flanks of a 3D surface (n_y -> 0) the equation would otherwise pull the
// base into tension and cancel its cohesion.
double bishop_factor(const SlopeSection& s, const std::vector<Column>& columns,
                     double weight_moment, double end_moment) {
  if (columns.size() < 5 || weight_moment == 0)
    return 0;
  const double direction = weight_moment > 0 ? 1.0 : -1.0;
  double factor = 1.5;
  for (int iteration = 0; iteration < 100; ++iteration) {
    double resisting = end_moment;
    for (const Column& c : columns) {
      const double sin_a = direction * c.downhill;
      const double m_alpha = std::max(0.2, c.normal_y + sin_a * s.tan_phi / factor);
      const double normal =
          std::max(0.0, (c.weight - s.cohesion * c.area * sin_a / factor) / m_alpha);
      resisting += c.arm * (s.cohesion * c.area + normal * s.tan_phi);
    }
    const double next = resisting / std::abs(weight_moment);
    const bool settled = std::abs(next - factor) < 1e-10 * next;
    factor = next;
    if (settled)
      break;
  }
  return factor;
}

bool reaches_below_base(const SlopeSection& s, double centre_y, double radius) {
  return radius <= 0 || centre_y - radius < s.base_y - 1e-12;
}

} // namespace

SlipCircle bishop_circle(const SlopeSection& s, double centre_x, double centre_y, double radius,
                         double width, double end_stress_ratio) {
  SlipCircle c{0, centre_x, centre_y, radius};
  if (reaches_below_base(s, centre_y, radius))
    return c;
  // Per unit width; the two end planes' share of it is 2 M_end / W.
  std::vector<Column> columns;
  const double moment = add_columns(s, centre_x, centre_y, radius, 1.0, 1.0, columns);
  const double ends =
      width > 0 ? 2 * end_plane_moment(s, centre_x, centre_y, radius, end_stress_ratio) / width
                : 0.0;
  c.factor = bishop_factor(s, columns, moment, ends);
  return c;
}

SlipSurface bishop_surface(const SlopeSection& s, const SlipSurface& surface, double width,
                           double end_stress_ratio) {
  SlipSurface g = surface;
  g.factor = 0;
  const double big_r = g.radius, p = g.exponent;
  if (reaches_below_base(s, g.centre_y, big_r) || !(g.length > 0))
    return g;
  // Over the half-width from the wall at z = 0 to the mid-plane; the other half mirrors it.
  const double dz = width / 2 / kStrips;
  const auto radius_at = [&](double z) {
    const double zeta = std::abs(2 * (z - width / 2) / g.length);
    return zeta < 1 ? big_r * std::pow(1 - std::pow(zeta, p), 1 / p) : 0.0;
  };
  std::vector<Column> columns;
  double moment = 0;
  for (int k = 0; k < kStrips; ++k) {
    const double z = (k + 0.5) * dz;
    const double r = radius_at(z);
    if (r <= 0)
      continue;
    // r' from r^p = R^p (1 - zeta^p): r' = R^p zeta^(p - 1) (2 / L) / r^(p - 1), rising with z
    // towards the mid-plane.
    const double zeta = std::abs(2 * (z - width / 2) / g.length);
    const double slope =
        std::pow(big_r, p) * std::pow(zeta, p - 1) * 2 / g.length / std::pow(r, p - 1);
    moment += add_columns(s, g.centre_x, g.centre_y, r, dz, std::sqrt(1 + slope * slope), columns);
  }
  const double wall_radius = radius_at(0);
  const double ends =
      wall_radius > 0 ? end_plane_moment(s, g.centre_x, g.centre_y, wall_radius, end_stress_ratio)
                      : 0.0;
  g.factor = bishop_factor(s, columns, moment, ends);
  return g;
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

SlipSurface critical_surface(const SlopeSection& s, double width, double end_stress_ratio,
                             const std::vector<double>& exponents) {
  const double height = *std::max_element(s.surface_y.begin(), s.surface_y.end()) - s.base_y;
  const SlipCircle cylinder = critical_circle(s, width, end_stress_ratio);
  SlipSurface best{cylinder.factor, cylinder.centre_x, cylinder.centre_y, cylinder.radius};
  // Pattern search in (centre, clearance, log length) from the critical cylinder's axis and a
  // given length, down to a step of H / 1000 (and 0.1 % of the length).
  const auto refine = [&](SlipSurface start) {
    start = bishop_surface(s, start, width, end_stress_ratio);
    for (double step = height / 16; step > height / 1000;) {
      const SlipSurface from = start;
      const double clearance = from.centre_y - s.base_y - from.radius;
      const double stretch = std::exp(step / height);
      const std::array<std::array<double, 4>, 8> moves{{{step, 0, 0, 1},
                                                        {-step, 0, 0, 1},
                                                        {0, step, 0, 1},
                                                        {0, -step, 0, 1},
                                                        {0, 0, step, 1},
                                                        {0, 0, -step, 1},
                                                        {0, 0, 0, stretch},
                                                        {0, 0, 0, 1 / stretch}}};
      for (const auto& m : moves) {
        if (clearance + m[2] < 0)
          continue;
        SlipSurface trial = from;
        trial.centre_x += m[0];
        trial.centre_y += m[1];
        trial.radius = trial.centre_y - s.base_y - (clearance + m[2]);
        trial.length *= m[3];
        trial = bishop_surface(s, trial, width, end_stress_ratio);
        if (trial.factor > 0 && trial.factor < start.factor)
          start = trial;
      }
      if (start.factor >= from.factor)
        step /= 2;
    }
    return start;
  };
  for (double p : exponents) {
    // The lengths that reach the walls and those that miss them are separate valleys: refine
    // the best start of each.
    SlipSurface reaching{}, missing{};
    for (double ratio : {0.5, 0.7, 0.85, 1.0, 1.05, 1.1, 1.2, 1.35, 1.5, 2.0, 3.0, 5.0}) {
      SlipSurface trial{0, cylinder.centre_x, cylinder.centre_y, cylinder.radius, ratio * width, p};
      trial = bishop_surface(s, trial, width, end_stress_ratio);
      SlipSurface& slot = ratio > 1 ? reaching : missing;
      if (trial.factor > 0 && (slot.factor == 0 || trial.factor < slot.factor))
        slot = trial;
    }
    for (const SlipSurface& start : {reaching, missing}) {
      if (start.factor == 0)
        continue;
      const SlipSurface found = refine(start);
      if (found.factor > 0 && found.factor < best.factor)
        best = found;
    }
  }
  return best;
}

} // namespace talus::verify_cases
