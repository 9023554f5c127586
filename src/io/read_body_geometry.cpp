// The geometry of a body: its shape keys, a simple polygon, and that it lies inside the grid.
#include "validator.hpp"

#include "talus/core/body_geometry.hpp"

#include <optional>

namespace talus::detail {

namespace {

constexpr std::size_t kMaxPolygonVertices = 4096;

double cross(const Vec2& a, const Vec2& b) {
  return a.x() * b.y() - a.y() * b.x();
}

int orientation(const Vec2& a, const Vec2& b, const Vec2& c) {
  const double o = cross(b - a, c - a);
  return (o > 0) - (o < 0);
}

bool on_segment(const Vec2& a, const Vec2& b, const Vec2& p) {
  return std::min(a.x(), b.x()) <= p.x() && p.x() <= std::max(a.x(), b.x()) &&
         std::min(a.y(), b.y()) <= p.y() && p.y() <= std::max(a.y(), b.y());
}

/// Closed segments [p1, p2] and [q1, q2] share at least one point.
bool segments_touch(const Vec2& p1, const Vec2& p2, const Vec2& q1, const Vec2& q2) {
  const int o1 = orientation(p1, p2, q1), o2 = orientation(p1, p2, q2);
  const int o3 = orientation(q1, q2, p1), o4 = orientation(q1, q2, p2);
  if (o1 != o2 && o3 != o4)
    return true;
  return (o1 == 0 && on_segment(p1, p2, q1)) || (o2 == 0 && on_segment(p1, p2, q2)) ||
         (o3 == 0 && on_segment(q1, q2, p1)) || (o4 == 0 && on_segment(q1, q2, p2));
}

} // namespace

void Validator::body_shape(const Map& m, BodySpec& b) const {
  b.shape = choice(m.required("shape"), body_shape_choices());
  struct ShapeKeys {
    BodyShape shape;
    const char* name;
    std::vector<std::string> keys;
  };
  static const std::array<ShapeKeys, 3> shapes{{{BodyShape::Rectangle, "rectangle", {"min", "max"}},
                                                {BodyShape::Disc, "disc", {"centre", "radius"}},
                                                {BodyShape::Polygon, "polygon", {"vertices"}}}};
  const ShapeKeys* mine = nullptr;
  for (const auto& s : shapes)
    if (s.shape == b.shape)
      mine = &s;
  for (const auto& s : shapes) {
    if (s.shape == b.shape)
      continue;
    for (const auto& key : s.keys)
      if (m.has(key))
        fail(m.key(key), "key '" + key + "' does not apply to shape " + mine->name + " (" +
                             mine->name + " takes " + join(mine->keys) + ")");
  }

  switch (b.shape) {
  case BodyShape::Rectangle: {
    b.min = vec2(m.required("min"));
    const Item max = m.required("max");
    b.max = vec2(max);
    if (!(b.max.x() > b.min.x() && b.max.y() > b.min.y()))
      fail(max, "max must be greater than min in both x and y (min " + vec(b.min) + ", max " +
                    vec(b.max) + ")");
    break;
  }
  case BodyShape::Disc:
    b.centre = vec2(m.required("centre"));
    b.radius = positive(m.required("radius"));
    break;
  case BodyShape::Polygon: {
    const Item vertices = m.required("vertices");
    const std::vector<Item> items = list(vertices);
    if (items.size() < 3)
      fail(vertices,
           "a polygon needs at least 3 vertices (got " + std::to_string(items.size()) + ")");
    // The simplicity test below compares every pair of edges.
    if (items.size() > kMaxPolygonVertices)
      fail(vertices, fmt::format("a polygon may have at most {} vertices (got {})",
                                 kMaxPolygonVertices, items.size()));
    for (const Item& v : items)
      b.vertices.push_back(vec2(v));
    const std::size_t n = b.vertices.size();
    double area2 = 0;
    Vec2 lo = b.vertices[0], hi = b.vertices[0];
    for (std::size_t i = 0; i < n; ++i) {
      area2 += cross(b.vertices[i], b.vertices[(i + 1) % n]);
      lo = lo.cwiseMin(b.vertices[i]);
      hi = hi.cwiseMax(b.vertices[i]);
    }
    const double tiny = 1e-12 * (hi - lo).squaredNorm();
    // What is wrong, in the order that names the real cause: all vertices on one line, a vertex
    // given twice in a row, edges that cross (a bow tie has zero signed area too), zero area.
    bool collinear = true;
    for (std::size_t i = 2; i < n && collinear; ++i)
      collinear =
          std::abs(cross(b.vertices[1] - b.vertices[0], b.vertices[i] - b.vertices[0])) <= tiny;
    if (collinear)
      fail(vertices, "the polygon has zero area: its vertices lie on one line");
    for (std::size_t i = 0; i < n; ++i)
      if ((b.vertices[i] - b.vertices[(i + 1) % n]).squaredNorm() <= tiny)
        fail(items[(i + 1) % n], fmt::format("vertex {} repeats vertex {} (vertices are numbered "
                                             "from 0)",
                                             (i + 1) % n, i));
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = i + 2; j < n; ++j) {
        if (i == 0 && j == n - 1)
          continue; // adjacent through the closing edge
        if (segments_touch(b.vertices[i], b.vertices[i + 1], b.vertices[j],
                           b.vertices[(j + 1) % n]))
          fail(vertices, fmt::format("the polygon is not simple: edge {}-{} touches edge {}-{} "
                                     "(vertices are numbered from 0)",
                                     i, i + 1, j, (j + 1) % n));
      }
    if (std::abs(area2) <= tiny)
      fail(vertices, "the polygon has zero area");
    break;
  }
  }
}

void Validator::body_inside_grid(const Map& m, const BodySpec& b, const GridSpec& g) const {
  const Vec2 lo = g.origin, hi = g.origin + g.extent;
  const double tol = 1e-12 * (g.origin.cwiseAbs().maxCoeff() + g.extent.maxCoeff());
  const auto inside = [&](const Vec2& p) {
    return p.x() >= lo.x() - tol && p.x() <= hi.x() + tol && p.y() >= lo.y() - tol &&
           p.y() <= hi.y() + tol;
  };
  std::string grid_box = fmt::format("the grid covers x in [{}, {}], y in [{}, {}]", num(lo.x()),
                                     num(hi.x()), num(lo.y()), num(hi.y()));
  for (const char* key : {"grid.origin", "grid.extent"})
    if (const AppliedOverride* o = origin(YAML::Mark::null_mark(), key)) {
      grid_box += " (the grid was changed by --set " + o->text + ")";
      break;
    }
  const std::string head = "body '" + b.name + "' extends outside the grid: ";
  switch (b.shape) {
  case BodyShape::Rectangle:
    if (!inside(b.min))
      fail(m["min"], head + "min " + vec(b.min) + " lies outside; " + grid_box);
    if (!inside(b.max))
      fail(m["max"], head + "max " + vec(b.max) + " lies outside; " + grid_box);
    break;
  case BodyShape::Disc: {
    if (!inside(b.centre))
      fail(m["centre"], head + "centre " + vec(b.centre) + " lies outside; " + grid_box);
    const Vec2 r(b.radius, b.radius);
    const Vec2 dlo = b.centre - r, dhi = b.centre + r;
    if (!inside(dlo) || !inside(dhi))
      fail(m["radius"], head +
                            fmt::format("the disc covers x in [{}, {}], y in [{}, {}]; ",
                                        num(dlo.x()), num(dhi.x()), num(dlo.y()), num(dhi.y())) +
                            grid_box);
    break;
  }
  case BodyShape::Polygon: {
    const Item vertices = m["vertices"];
    for (std::size_t i = 0; i < b.vertices.size(); ++i)
      if (!inside(b.vertices[i]))
        fail(Item{vertices.node[i], mark_or(vertices.node[i], vertices.mark),
                  child_path(vertices.path, i)},
             head + "vertex " + vec(b.vertices[i]) + " lies outside; " + grid_box);
    break;
  }
  }
}

} // namespace talus::detail

namespace talus::detail {

namespace {

/// The cost of one inside test of a body (a polygon tests every edge).
double inside_cost(const BodySpec& b) {
  return b.shape == BodyShape::Polygon ? static_cast<double>(b.vertices.size()) : 1.0;
}

bool boxes_overlap(const BodySpec& a, const BodySpec& b) {
  Vec2 alo = Vec2::Zero(), ahi = Vec2::Zero(), blo = Vec2::Zero(), bhi = Vec2::Zero();
  bounding_box(a, alo, ahi);
  bounding_box(b, blo, bhi);
  return alo.x() <= bhi.x() && blo.x() <= ahi.x() && alo.y() <= bhi.y() && blo.y() <= ahi.y();
}

/// The first lattice site of body a (spacing h / particles_per_cell, its placement offset) that
/// lies inside both a and b and inside the grid: a place where both bodies would put a point.
/// At most about `budget` inside tests are spent (every k-th site beyond that), so that the check
/// stays well under a second for any bodies the memory estimate lets through.
std::optional<Vec2> shared_site(const GridSpec& g, const BodySpec& a, const BodySpec& b,
                                double budget) {
  Vec2 alo = Vec2::Zero(), ahi = Vec2::Zero(), blo = Vec2::Zero(), bhi = Vec2::Zero();
  bounding_box(a, alo, ahi);
  bounding_box(b, blo, bhi);
  const Vec2 lo = alo.cwiseMax(blo), hi = ahi.cwiseMin(bhi);
  if (!(lo.x() <= hi.x() && lo.y() <= hi.y()))
    return std::nullopt;
  const double spacing = g.cell_size / a.particles_per_cell;
  const Vec2 origin = g.origin + spacing * a.placement.offset;
  std::array<double, 2> first{}, count{};
  for (int d = 0; d < 2; ++d) {
    first[static_cast<std::size_t>(d)] = std::floor((lo[d] - origin[d]) / spacing);
    count[static_cast<std::size_t>(d)] =
        std::ceil((hi[d] - origin[d]) / spacing) - first[static_cast<std::size_t>(d)];
  }
  const double sites = count[0] * count[1];
  const double max_sites = std::max(1.0, budget / (inside_cost(a) + inside_cost(b)));
  const double stride = sites > max_sites ? std::ceil(std::sqrt(sites / max_sites)) : 1.0;
  const Vec2 grid_hi = g.origin + g.extent;
  for (double j = 0; j < count[1]; j += stride)
    for (double i = 0; i < count[0]; i += stride) {
      const Vec2 q = origin + spacing * Vec2(first[0] + i + 0.5, first[1] + j + 0.5);
      if ((q.array() < g.origin.array()).any() || (q.array() > grid_hi.array()).any())
        continue;
      if (inside_body(a, q) && inside_body(b, q))
        return q;
    }
  return std::nullopt;
}

} // namespace

// Two bodies that cover the same place would both put points there: twice the mass, moving as
// one (MPM has one velocity field), which no case means. Bodies may touch along an edge.
void Validator::bodies_apart(const std::vector<Item>& items, const std::vector<BodySpec>& bodies,
                             const GridSpec& grid) const {
  // About 4e7 inside tests in all (a few tenths of a second), shared among the pairs whose
  // bounding boxes meet.
  double pairs = 0;
  for (std::size_t j = 1; j < bodies.size(); ++j)
    for (std::size_t i = 0; i < j; ++i)
      pairs += boxes_overlap(bodies[i], bodies[j]) ? 1 : 0;
  const double budget = std::max(1e4, 2e7 / std::max(1.0, pairs));
  for (std::size_t j = 1; j < bodies.size(); ++j)
    for (std::size_t i = 0; i < j; ++i) {
      if (!boxes_overlap(bodies[i], bodies[j]))
        continue;
      std::optional<Vec2> q = shared_site(grid, bodies[j], bodies[i], budget);
      if (!q)
        q = shared_site(grid, bodies[i], bodies[j], budget);
      if (q)
        fail(items[j], fmt::format("body '{}' overlaps body '{}': the point {} lies in both, so "
                                   "both would put material points there (twice the mass); "
                                   "bodies may touch along an edge but not overlap",
                                   bodies[j].name, bodies[i].name, vec(*q)));
    }
}

} // namespace talus::detail
