// Boundary conditions and loads of a case file: faces, point loads, tractions, prescribed
// displacements (docs/case-format.md).
#include "validator.hpp"

namespace talus::detail {

BoundarySpec Validator::boundaries(const Item& it) const {
  const Map m(*this, it, {"x_min", "x_max", "y_min", "y_max"});
  const std::vector<std::pair<std::string, FaceCondition>> options{
      {"free", FaceCondition::Free},
      {"fixed", FaceCondition::Fixed},
      {"roller", FaceCondition::Roller}};
  BoundarySpec b;
  const std::pair<const char*, FaceCondition*> faces[] = {
      {"x_min", &b.x_min}, {"x_max", &b.x_max}, {"y_min", &b.y_min}, {"y_max", &b.y_max}};
  for (const auto& [key, field] : faces)
    if (m.has(key))
      *field = choice(m[key], options);
  return b;
}

std::vector<PointLoadSpec> Validator::point_loads(const Item& it, const CaseSpec& spec) const {
  std::vector<PointLoadSpec> out;
  UniqueNames names(*this, "point load");
  const std::vector<Item> items = list(it);
  for (std::size_t i = 0; i < items.size(); ++i) {
    const Map m(*this, items[i], {"name", "point", "force"});
    PointLoadSpec p;
    p.where = locate(m.self());
    if (m.has("name")) {
      p.name = name(m["name"]);
      names.add(p.name, m["name"], items[i].path);
    } else {
      p.name = "load" + std::to_string(i);
      names.add(p.name, m.self(), items[i].path + " (default name)");
    }
    const Item point = m.required("point");
    p.point = vec2(point);
    if (!inside_grid(p.point, spec.grid))
      fail(point,
           "point load at " + vec(p.point) + " lies outside the grid; " + grid_box(spec.grid));
    p.force = vec2(m.required("force"));
    out.push_back(std::move(p));
  }
  return out;
}

std::vector<TractionSpec> Validator::tractions(const Item& it, const CaseSpec& spec) const {
  std::vector<TractionSpec> out;
  std::vector<std::string> body_names;
  for (const auto& b : spec.bodies)
    body_names.push_back(b.name);
  for (const Item& item : list(it)) {
    const Map m(*this, item, {"body", "side", "traction", "constant"});
    TractionSpec t;
    t.where = locate(m.self());
    const Item body = m.required("body");
    t.body = name(body);
    const auto found = std::find(body_names.begin(), body_names.end(), t.body);
    if (found == body_names.end()) {
      std::string what =
          "unknown body '" + shown(t.body) + "' (defined bodies: " + join(body_names) + ")";
      const std::string guess = closest_match(t.body, body_names);
      if (!guess.empty())
        what += "; did you mean '" + guess + "'?";
      fail(body, what);
    }
    t.body_index = static_cast<int>(found - body_names.begin());
    const BodyShape shape = spec.bodies[static_cast<std::size_t>(t.body_index)].shape;
    if (shape != BodyShape::Rectangle)
      fail(body, "a traction needs a rectangle body, but body '" + t.body + "' is a " +
                     (shape == BodyShape::Disc ? "disc" : "polygon"));
    t.side = choice<Side>(m.required("side"), {{"left", Side::Left},
                                               {"right", Side::Right},
                                               {"bottom", Side::Bottom},
                                               {"top", Side::Top}});
    t.traction = vec2(m.required("traction"));
    if (m.has("constant"))
      t.constant = boolean(m["constant"]);
    out.push_back(std::move(t));
  }
  return out;
}

std::vector<PrescribedSpec> Validator::prescribed(const Item& it, const CaseSpec& spec) const {
  std::vector<PrescribedSpec> out;
  const Vec2 lo = spec.grid.origin, hi = spec.grid.origin + spec.grid.extent;
  const double tol = 1e-9 * spec.grid.cell_size;
  for (const Item& item : list(it)) {
    const Map m(*this, item, {"name", "min", "max", "displacement"});
    PrescribedSpec p;
    p.where = locate(m.self());
    const Item name_item = m.required("name");
    p.name = name(name_item);
    column_name(name_item, p.name);
    for (const auto& other : out)
      if (other.name == p.name)
        fail(name_item, "duplicate name '" + p.name + "'");
    p.min = vec2(m.required("min"));
    const Item max_item = m.required("max");
    p.max = vec2(max_item);
    if (!(p.max.x() >= p.min.x() && p.max.y() >= p.min.y()))
      fail(max_item, "max must not be below min in either direction");
    for (const auto& [key, corner] : {std::pair{"min", p.min}, std::pair{"max", p.max}})
      if ((corner.array() < lo.array() - tol).any() || (corner.array() > hi.array() + tol).any())
        fail(m[key], std::string(key) + " lies outside the grid");
    const Item d = m.required("displacement");
    if (!d.node.IsSequence() || d.node.size() != 2)
      fail(d, "expected a 2-element list [ux, uy]; write ~ (null) for a free component");
    for (std::size_t i = 0; i < 2; ++i) {
      const Item c{d.node[i], mark_or(d.node[i], d.mark), child_path(d.path, i)};
      if (c.node.IsNull())
        continue;
      p.displacement[i] = number(c);
    }
    if (!p.displacement[0] && !p.displacement[1])
      fail(d, "both components are free (~); prescribe at least one");
    if (const std::string stage = explicit_stage(spec); !stage.empty())
      fail(m.self(), "prescribed displacements need an implicit analysis "
                     "(implicit_quasistatic or implicit_dynamic), but " +
                         stage + " is explicit");
    out.push_back(std::move(p));
  }
  return out;
}

// A fixed explicit step above h / c_p amplifies the stiffest mode of the grid (the CFL limit of
// the lumped-mass central-difference scheme); such a step is refused, not run into a blow-up.

} // namespace talus::detail
