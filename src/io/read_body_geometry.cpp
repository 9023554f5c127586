// The geometry of a body: its shape keys, a simple polygon, and that it lies inside the grid.
#include "validator.hpp"

#include "talus/scene/body_geometry.hpp"

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
  b.shape = choice(m.required("shape"), body_shape_choices(dimension_));
  struct ShapeKeys {
    BodyShape shape;
    const char* name;
    std::vector<std::string> keys;
  };
  static const std::vector<ShapeKeys> plane{{BodyShape::Rectangle, "rectangle", {"min", "max"}},
                                            {BodyShape::Disc, "disc", {"centre", "radius"}},
                                            {BodyShape::Polygon, "polygon", {"vertices"}}};
  static const std::vector<ShapeKeys> solid{
      {BodyShape::Rectangle, "box", {"min", "max"}},
      {BodyShape::Disc, "sphere", {"centre", "radius"}},
      {BodyShape::Cylinder, "cylinder", {"axis", "radius"}},
      {BodyShape::Polygon, "prism", {"vertices", "z_min", "z_max"}}};
  const std::vector<ShapeKeys>& shapes = dimension_ == 3 ? solid : plane;
  const ShapeKeys* mine = nullptr;
  for (const auto& s : shapes)
    if (s.shape == b.shape)
      mine = &s;
  for (const char* key : {"min", "max", "centre", "radius", "vertices", "axis", "z_min", "z_max"})
    if (m.has(key) && std::find(mine->keys.begin(), mine->keys.end(), key) == mine->keys.end())
      fail(m.key(key), std::string("key '") + key + "' does not apply to shape " + mine->name +
                           " (" + mine->name + " takes " + join(mine->keys) + ")");

  switch (b.shape) {
  case BodyShape::Rectangle: {
    b.min = point(m.required("min"));
    const Item max = m.required("max");
    b.max = point(max);
    if (!below_along_all(b.min, b.max, dimension_))
      fail(max, std::string("max must be greater than min in ") +
                    (dimension_ == 3 ? "x, y and z" : "both x and y") + " (min " +
                    vec(b.min, dimension_) + ", max " + vec(b.max, dimension_) + ")");
    break;
  }
  case BodyShape::Disc:
    b.centre = point(m.required("centre"));
    b.radius = positive(m.required("radius"));
    break;
  case BodyShape::Cylinder: {
    const Item axis = m.required("axis");
    if (!axis.node.IsSequence() || axis.node.size() != 2)
      fail(axis, "expected the two ends of the axis, [[x0, y0, z0], [x1, y1, z1]], got " +
                     describe(axis.node));
    b.axis_start =
        point(Item{axis.node[0], mark_or(axis.node[0], axis.mark), child_path(axis.path, 0)});
    b.axis_end =
        point(Item{axis.node[1], mark_or(axis.node[1], axis.mark), child_path(axis.path, 1)});
    if ((b.axis_end - b.axis_start).norm() <= 1e-12 * (b.axis_start.norm() + b.axis_end.norm()))
      fail(axis, "the two ends of the axis coincide: the cylinder has no length");
    b.radius = positive(m.required("radius"));
    break;
  }
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
      b.vertices.push_back(plane_point(v));
    const std::size_t count = b.vertices.size();
    double area2 = 0;
    Vec2 lo = b.vertices[0], hi = b.vertices[0];
    for (std::size_t i = 0; i < count; ++i) {
      area2 += cross(b.vertices[i], b.vertices[(i + 1) % count]);
      lo = lo.cwiseMin(b.vertices[i]);
      hi = hi.cwiseMax(b.vertices[i]);
    }
    const double tiny = 1e-12 * (hi - lo).squaredNorm();
    // What is wrong, in the order that names the real cause: all vertices on one line, a vertex
    // given twice in a row, edges that cross (a bow tie has zero signed area too), zero area.
    bool collinear = true;
    for (std::size_t i = 2; i < count && collinear; ++i)
      collinear =
          std::abs(cross(b.vertices[1] - b.vertices[0], b.vertices[i] - b.vertices[0])) <= tiny;
    if (collinear)
      fail(vertices, "the polygon has zero area: its vertices lie on one line");
    for (std::size_t i = 0; i < count; ++i)
      if ((b.vertices[i] - b.vertices[(i + 1) % count]).squaredNorm() <= tiny)
        fail(items[(i + 1) % count], fmt::format("vertex {} repeats vertex {} (vertices are "
                                                 "numbered from 0)",
                                                 (i + 1) % count, i));
    for (std::size_t i = 0; i < count; ++i)
      for (std::size_t j = i + 2; j < count; ++j) {
        if (i == 0 && j == count - 1)
          continue; // adjacent through the closing edge
        if (segments_touch(b.vertices[i], b.vertices[i + 1], b.vertices[j],
                           b.vertices[(j + 1) % count]))
          fail(vertices, fmt::format("the polygon is not simple: edge {}-{} touches edge {}-{} "
                                     "(vertices are numbered from 0)",
                                     i, i + 1, j, (j + 1) % count));
      }
    if (std::abs(area2) <= tiny)
      fail(vertices, "the polygon has zero area");
    if (dimension_ == 3) {
      b.z_min = number(m.required("z_min"));
      const Item z_max = m.required("z_max");
      b.z_max = number(z_max);
      if (!(b.z_max > b.z_min))
        fail(z_max, "z_max must be greater than z_min (" + num(b.z_min) + ")");
    }
    break;
  }
  }
}

void Validator::body_inside_grid(const Map& m, const BodySpec& b, const GridSpec& g) const {
  std::string box = grid_box(g);
  for (const char* key : {"grid.origin", "grid.extent"})
    if (const AppliedOverride* o = origin(YAML::Mark::null_mark(), key)) {
      box += " (the grid was changed by --set " + o->text + ")";
      break;
    }
  const std::string head = "body '" + b.name + "' extends outside the grid: ";
  const auto covers = [&](const Vec3& lo, const Vec3& hi) {
    std::string s = fmt::format("covers x in [{}, {}], y in [{}, {}]", num(lo.x()), num(hi.x()),
                                num(lo.y()), num(hi.y()));
    if (dimension_ == 3)
      s += fmt::format(", z in [{}, {}]", num(lo.z()), num(hi.z()));
    return s;
  };
  Vec3 lo, hi;
  bounding_box(b, dimension_, lo, hi);
  switch (b.shape) {
  case BodyShape::Rectangle:
    if (!inside_grid(b.min, g))
      fail(m["min"], head + "min " + vec(b.min, dimension_) + " lies outside; " + box);
    if (!inside_grid(b.max, g))
      fail(m["max"], head + "max " + vec(b.max, dimension_) + " lies outside; " + box);
    break;
  case BodyShape::Disc:
    if (!inside_grid(b.centre, g))
      fail(m["centre"], head + "centre " + vec(b.centre, dimension_) + " lies outside; " + box);
    if (!inside_grid(lo, g) || !inside_grid(hi, g))
      fail(m["radius"],
           head + "the " + (dimension_ == 3 ? "sphere " : "disc ") + covers(lo, hi) + "; " + box);
    break;
  case BodyShape::Cylinder:
    if (!inside_grid(lo, g) || !inside_grid(hi, g))
      fail(m["radius"], head + "the cylinder " + covers(lo, hi) + "; " + box);
    break;
  case BodyShape::Polygon: {
    const Item vertices = m["vertices"];
    for (std::size_t i = 0; i < b.vertices.size(); ++i)
      if (!inside_grid(Vec3(b.vertices[i].x(), b.vertices[i].y(), g.origin.z()), g))
        fail(Item{vertices.node[i], mark_or(vertices.node[i], vertices.mark),
                  child_path(vertices.path, i)},
             head + "vertex " + vec(b.vertices[i]) + " lies outside; " + box);
    if (!inside_grid(lo, g) || !inside_grid(hi, g))
      fail(m["z_max"], head + "the prism " + covers(lo, hi) + "; " + box);
    break;
  }
  }
}

void Validator::body_off_axis(const Map& m, const BodySpec& b) const {
  const std::string head = "body '" + b.name + "' reaches r = x < 0 in an axisymmetric case ";
  const char* fix = "; a body of revolution lies in r >= 0, its axis at x = 0";
  switch (b.shape) {
  case BodyShape::Rectangle:
    if (b.min.x() < 0)
      fail(m["min"], head + "(min x = " + num(b.min.x()) + ")" + fix);
    break;
  case BodyShape::Disc:
    if (b.centre.x() - b.radius < 0)
      fail(m["radius"], head + "(the disc reaches x = " + num(b.centre.x() - b.radius) + ")" + fix);
    break;
  case BodyShape::Polygon: {
    const Item vertices = m["vertices"];
    for (std::size_t i = 0; i < b.vertices.size(); ++i)
      if (b.vertices[i].x() < 0)
        fail(Item{vertices.node[i], mark_or(vertices.node[i], vertices.mark),
                  child_path(vertices.path, i)},
             head + "(vertex " + vec(b.vertices[i]) + ")" + fix);
    break;
  }
  case BodyShape::Cylinder: // a 3D shape: the reader refused it in 2D
    break;
  }
}

} // namespace talus::detail

namespace talus::detail {

namespace {

/// The cost of one inside test of a body (a polygon tests every edge).
double inside_cost(const BodySpec& b) {
  return b.shape == BodyShape::Polygon ? static_cast<double>(b.vertices.size()) : 1.0;
}

bool boxes_overlap(const BodySpec& a, const BodySpec& b, int dimension) {
  Vec3 alo, ahi, blo, bhi;
  bounding_box(a, dimension, alo, ahi);
  bounding_box(b, dimension, blo, bhi);
  return (alo.array() <= bhi.array()).all() && (blo.array() <= ahi.array()).all();
}

/// The first lattice site of body a (spacing h / particles_per_cell, its placement offset) that
/// lies inside both a and b and inside the grid: a place where both bodies would put a point.
/// At most about `budget` inside tests are spent (every k-th site beyond that), so that the check
/// stays well under a second for any bodies the memory estimate lets through.
std::optional<Vec3> shared_site(const GridSpec& g, const BodySpec& a, const BodySpec& b,
                                double budget) {
  Vec3 alo, ahi, blo, bhi;
  bounding_box(a, g.dimension, alo, ahi);
  bounding_box(b, g.dimension, blo, bhi);
  const Vec3 lo = alo.cwiseMax(blo), hi = ahi.cwiseMin(bhi);
  if (!(lo.array() <= hi.array()).all())
    return std::nullopt;
  const double spacing = g.cell_size / a.particles_per_cell;
  const Vec3 origin = g.origin + spacing * a.placement.offset;
  const int dims = g.dimension;
  std::array<double, 3> first{}, count{1, 1, 1};
  double sites = 1;
  for (int d = 0; d < dims; ++d) {
    const auto k = static_cast<std::size_t>(d);
    first[k] = std::floor((lo[d] - origin[d]) / spacing);
    count[k] = std::ceil((hi[d] - origin[d]) / spacing) - first[k];
    sites *= count[k];
  }
  const double max_sites = std::max(1.0, budget / (inside_cost(a) + inside_cost(b)));
  const double stride =
      sites > max_sites ? std::ceil(std::pow(sites / max_sites, 1.0 / dims)) : 1.0;
  for (double k = 0; k < count[2]; k += stride)
    for (double j = 0; j < count[1]; j += stride)
      for (double i = 0; i < count[0]; i += stride) {
        Vec3 q =
            origin + spacing * Vec3(first[0] + i + 0.5, first[1] + j + 0.5, first[2] + k + 0.5);
        if (dims == 2)
          q.z() = 0.0;
        if (!inside_grid(q, g))
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
      pairs += boxes_overlap(bodies[i], bodies[j], grid.dimension) ? 1 : 0;
  const double budget = std::max(1e4, 2e7 / std::max(1.0, pairs));
  for (std::size_t j = 1; j < bodies.size(); ++j)
    for (std::size_t i = 0; i < j; ++i) {
      if (!boxes_overlap(bodies[i], bodies[j], grid.dimension))
        continue;
      std::optional<Vec3> q = shared_site(grid, bodies[j], bodies[i], budget);
      if (!q)
        q = shared_site(grid, bodies[i], bodies[j], budget);
      if (q)
        fail(items[j], fmt::format("body '{}' overlaps body '{}': the point {} lies in both, so "
                                   "both would put material points there (twice the mass); "
                                   "bodies may touch along an edge but not overlap",
                                   bodies[j].name, bodies[i].name, vec(*q, grid.dimension)));
    }
}

} // namespace talus::detail
