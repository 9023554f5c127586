#pragma once
// The geometry of a body of a case (rectangle, disc, polygon): which points lie inside it and
// its bounding box. Shared by the scene, which fills bodies with points, and the case reader,
// which refuses bodies that overlap.
#include "talus/io/case_spec.hpp"

#include <vector>

namespace talus {

inline bool inside_polygon(const std::vector<Vec2>& poly, const Vec2& q) {
  // Crossing-number test on a half-open rule, so a lattice point on an edge is counted once.
  bool in = false;
  const std::size_t n = poly.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const Vec2& a = poly[i];
    const Vec2& b = poly[j];
    if ((a.y() > q.y()) != (b.y() > q.y())) {
      const double x_cross = a.x() + (q.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y());
      if (q.x() < x_cross)
        in = !in;
    }
  }
  return in;
}

inline bool inside_body(const BodySpec& b, const Vec2& q) {
  switch (b.shape) {
  case BodyShape::Rectangle:
    return q.x() >= b.min.x() && q.x() <= b.max.x() && q.y() >= b.min.y() && q.y() <= b.max.y();
  case BodyShape::Disc:
    return (q - b.centre).squaredNorm() <= b.radius * b.radius;
  case BodyShape::Polygon:
    return inside_polygon(b.vertices, q);
  }
  return false;
}

inline void bounding_box(const BodySpec& b, Vec2& lo, Vec2& hi) {
  switch (b.shape) {
  case BodyShape::Rectangle:
    lo = b.min;
    hi = b.max;
    return;
  case BodyShape::Disc:
    lo = b.centre.array() - b.radius;
    hi = b.centre.array() + b.radius;
    return;
  case BodyShape::Polygon:
    lo = hi = b.vertices.front();
    for (const Vec2& v : b.vertices) {
      lo = lo.cwiseMin(v);
      hi = hi.cwiseMax(v);
    }
    return;
  }
}

} // namespace talus
