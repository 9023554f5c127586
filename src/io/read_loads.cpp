// Boundary conditions and loads of a case file: faces, point loads, tractions, prescribed
// displacements (docs/case-format.md).
#include "validator.hpp"

namespace talus::detail {

BoundarySpec Validator::boundaries(const Item& it, const CaseSpec& spec) const {
  std::vector<std::string> keys;
  for (int f = 0; f < face_count(dimension_); ++f)
    keys.push_back(face_name(f));
  if (dimension_ == 2)
    for (const char* key : {"z_min", "z_max"})
      if (it.node.IsMap() && it.node[key])
        fail(Item{it.node[key], mark_or(it.node[key], it.mark), child_path(it.path, key)},
             std::string("a 2D case has no face ") + key +
                 " (dimension: 2; faces x_min, x_max, "
                 "y_min, y_max)");
  const Map m(*this, it, keys);
  const std::vector<std::pair<std::string, FaceCondition>> options{
      {"free", FaceCondition::Free},
      {"fixed", FaceCondition::Fixed},
      {"roller", FaceCondition::Roller},
      {"platen", FaceCondition::Platen}};
  BoundarySpec b;
  for (int f = 0; f < face_count(dimension_); ++f) {
    if (!m.has(face_name(f)))
      continue;
    b[f] = choice(m[face_name(f)], options);
    if (b[f] != FaceCondition::Platen)
      continue;
    // The explicit step has no unknown the face's nodes could share.
    if (const std::string stage = explicit_stage(spec); !stage.empty())
      fail(m[face_name(f)], "a platen needs an implicit analysis (implicit_quasistatic or "
                            "implicit_dynamic), but " +
                                stage + " is explicit");
  }
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
    p.point = this->point(point);
    if (!inside_grid(p.point, spec.grid))
      fail(point, "point load at " + vec(p.point, dimension_) + " lies outside the grid; " +
                      grid_box(spec.grid));
    p.force = this->point(m.required("force"));
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
    // The sides of a 2D rectangle by name; a 3D box adds back (z_min) and front (z_max).
    std::vector<std::pair<std::string, int>> sides{
        {"left", kXMin}, {"right", kXMax}, {"bottom", kYMin}, {"top", kYMax}};
    if (dimension_ == 3)
      sides.insert(sides.end(), {{"back", kZMin}, {"front", kZMax}});
    t.side = choice<int>(m.required("side"), sides);
    t.traction = this->point(m.required("traction"));
    if (m.has("constant"))
      t.constant = boolean(m["constant"]);
    out.push_back(std::move(t));
  }
  return out;
}

std::vector<PrescribedSpec> Validator::prescribed(const Item& it, const CaseSpec& spec) const {
  std::vector<PrescribedSpec> out;
  const Vec3 lo = spec.grid.origin, hi = spec.grid.origin + spec.grid.extent;
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
    p.min = point(m.required("min"));
    const Item max_item = m.required("max");
    p.max = point(max_item);
    for (int d = 0; d < dimension_; ++d)
      if (p.max[d] < p.min[d])
        fail(max_item, "max must not be below min in any direction");
    for (const auto& [key, corner] : {std::pair{"min", p.min}, std::pair{"max", p.max}})
      for (int d = 0; d < dimension_; ++d)
        if (corner[d] < lo[d] - tol || corner[d] > hi[d] + tol)
          fail(m[key], std::string(key) + " lies outside the grid");
    const Item d = m.required("displacement");
    if (!d.node.IsSequence() || d.node.size() != static_cast<std::size_t>(dimension_))
      fail(d,
           std::string("expected ") +
               (dimension_ == 3 ? "a 3-element list [ux, uy, uz]" : "a 2-element list [ux, uy]") +
               "; write ~ (null) for a free component");
    for (std::size_t i = 0; i < d.node.size(); ++i) {
      const Item c{d.node[i], mark_or(d.node[i], d.mark), child_path(d.path, i)};
      if (c.node.IsNull())
        continue;
      p.displacement[i] = number(c);
    }
    if (std::none_of(p.displacement.begin(), p.displacement.end(),
                     [](const std::optional<double>& u) { return u.has_value(); }))
      fail(d, "every component is free (~); prescribe at least one");
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
