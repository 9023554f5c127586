#pragma once
// The geometry of a body of a case: which points lie inside it and its bounding box. Shared by
// the scene, which fills bodies with points, and the case reader, which refuses bodies that
// overlap. Points are 3-vectors; a 2D case keeps z = 0 in every point and body, so the same
// tests serve both: a rectangle is a box of zero depth, a disc a sphere cut at z = 0, a polygon
// a prism from z_min = 0 to z_max = 0.
#include "talus/spec/case_spec.hpp"

#include <algorithm>
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

/// Whether q lies in the cylinder of radius r around the segment [a, b].
inline bool inside_cylinder(const Vec3& a, const Vec3& b, double r, const Vec3& q) {
  const Vec3 axis = b - a;
  const double t = axis.dot(q - a) / axis.squaredNorm();
  if (t < 0.0 || t > 1.0)
    return false;
  return (q - a - t * axis).squaredNorm() <= r * r;
}

inline bool inside_body(const BodySpec& b, const Vec3& q) {
  switch (b.shape) {
  case BodyShape::Rectangle:
    return (q.array() >= b.min.array()).all() && (q.array() <= b.max.array()).all();
  case BodyShape::Disc:
    return (q - b.centre).squaredNorm() <= b.radius * b.radius;
  case BodyShape::Polygon:
    return q.z() >= b.z_min && q.z() <= b.z_max && inside_polygon(b.vertices, q.head<2>());
  case BodyShape::Cylinder:
    return inside_cylinder(b.axis_start, b.axis_end, b.radius, q);
  }
  return false;
}

/// The body's axis-aligned bounding box, in the first `dimension` components (z stays 0 in 2D).
inline void bounding_box(const BodySpec& b, int dimension, Vec3& lo, Vec3& hi) {
  lo = hi = Vec3::Zero();
  switch (b.shape) {
  case BodyShape::Rectangle:
    lo = b.min;
    hi = b.max;
    break;
  case BodyShape::Disc:
    lo = b.centre.array() - b.radius;
    hi = b.centre.array() + b.radius;
    break;
  case BodyShape::Polygon:
    lo = Vec3(b.vertices.front().x(), b.vertices.front().y(), b.z_min);
    hi = Vec3(b.vertices.front().x(), b.vertices.front().y(), b.z_max);
    for (const Vec2& v : b.vertices) {
      lo.head<2>() = lo.head<2>().cwiseMin(v);
      hi.head<2>() = hi.head<2>().cwiseMax(v);
    }
    break;
  case BodyShape::Cylinder: {
    // Each axis end is a disc of radius r normal to the axis: along direction d it reaches
    // r sqrt(1 - n_d^2) beyond the end.
    const Vec3 n = (b.axis_end - b.axis_start).normalized();
    const Vec3 reach = b.radius * (Vec3::Ones() - n.cwiseProduct(n)).cwiseMax(0.0).cwiseSqrt();
    lo = b.axis_start.cwiseMin(b.axis_end) - reach;
    hi = b.axis_start.cwiseMax(b.axis_end) + reach;
    break;
  }
  }
  if (dimension == 2)
    lo.z() = hi.z() = 0.0;
}

} // namespace talus
