// The water section of a case file and the materials' saturated weights (docs/case-format.md,
// water).
#include "validator.hpp"

namespace talus::detail {

WaterSpec Validator::water(const Item& it, const CaseSpec& spec, bool stage) const {
  const Map m(*this, it,
              stage ? std::vector<std::string>{"unit_weight", "level", "phreatic"}
                    : std::vector<std::string>{"unit_weight", "level", "phreatic", "drained"});
  WaterSpec w;
  w.where = locate(m.self());
  if (m.has("unit_weight"))
    w.unit_weight = positive(m["unit_weight"]);
  if (m.has("drained"))
    w.drained = drained_faces(m["drained"]);
  // A consolidation case may go without a water table: its pore pressure is then the excess
  // over a hydrostatic state the case does not model.
  const bool consolidates = std::any_of(spec.materials.begin(), spec.materials.end(),
                                        [](const MaterialSpec& mat) { return mat.flow; });
  if (m.has("level") && m.has("phreatic"))
    fail(m.key("phreatic"), "give the phreatic surface once: level: y (a level water table) or "
                            "phreatic: [[x, y], ...] (a polyline of ascending x)");
  if (!m.has("level") && !m.has("phreatic")) {
    if (stage || !consolidates)
      fail(m.self(), "give the phreatic surface: level: y (a level water table) or phreatic: "
                     "[[x, y], ...] (a polyline of ascending x)");
    return w;
  }
  if (m.has("level")) {
    w.phreatic = {{0.0, number(m["level"])}};
  } else {
    const std::vector<Item> points = list(m["phreatic"]);
    if (points.empty())
      fail(m["phreatic"], "list at least one point [x, y] of the phreatic surface");
    for (const Item& p : points) {
      const std::vector<Item> xy = list(p);
      if (xy.size() != 2)
        fail(p, "a point of the phreatic surface is [x, y]: x across, y up (in 3D the surface "
                "is this polyline extruded along z); got " +
                    describe(p.node));
      const double x = number(xy[0]), y = number(xy[1]);
      if (!w.phreatic.empty() && !(x > w.phreatic.back()[0]))
        fail(xy[0], "the phreatic surface's x must ascend (" + shown(std::to_string(x)) +
                        " follows " + shown(std::to_string(w.phreatic.back()[0])) + ")");
      w.phreatic.push_back({x, y});
    }
  }
  const Vec3& g = spec.gravity;
  if (g.norm() == 0.0 || g.x() != 0.0 || g.y() > 0.0 || g.z() != 0.0)
    fail(m.self(), "water needs gravity along -y: its pore pressure is hydrostatic, u = gamma_w "
                   "(y_w - y) below the phreatic surface y_w");
  return w;
}

std::array<bool, 6> Validator::drained_faces(const Item& it) const {
  std::array<bool, 6> drained{};
  for (const Item& face : list(it)) {
    bool known = false;
    for (int f = 0; f < face_count(dimension_); ++f)
      if (face.node.IsScalar() && face.node.Scalar() == face_name(f)) {
        drained[static_cast<std::size_t>(f)] = known = true;
      }
    if (!known)
      fail(face, "a drained face is one of the grid's faces (" +
                     std::string(dimension_ == 3 ? "x_min, x_max, y_min, y_max, z_min, z_max"
                                                 : "x_min, x_max, y_min, y_max") +
                     "); got " + describe(face.node));
  }
  return drained;
}

std::optional<PoreFlowSpec> Validator::pore_flow(const Map& m) const {
  const char* const keys[] = {"permeability", "biot_coefficient", "biot_modulus",
                              "fluid_bulk_modulus", "porosity"};
  if (!m.has("permeability")) {
    for (const char* key : keys)
      if (m.has(key))
        fail(m.key(key), std::string("'") + key +
                             "' describes the pore water's flow; give the "
                             "material's permeability (m/s) too, or remove it");
    return std::nullopt;
  }
  PoreFlowSpec f;
  f.permeability = positive(m["permeability"]);
  if (m.has("biot_coefficient")) {
    const Item a = m["biot_coefficient"];
    f.biot_coefficient = number(a);
    if (!(f.biot_coefficient > 0 && f.biot_coefficient <= 1))
      fail(a, "must be in (0, 1] (got " + shown(a.node.Scalar()) + ")");
  }
  if (m.has("biot_modulus") && (m.has("fluid_bulk_modulus") || m.has("porosity")))
    fail(m.key("biot_modulus"), "give the storage once: biot_modulus M, or fluid_bulk_modulus "
                                "with porosity (1/M = n / K_f + (alpha - n)(1 - alpha) / K)");
  if (m.has("biot_modulus"))
    f.inverse_biot_modulus = 1.0 / positive(m["biot_modulus"]);
  if (m.has("fluid_bulk_modulus") != m.has("porosity"))
    fail(m.has("porosity") ? m.key("porosity") : m.key("fluid_bulk_modulus"),
         "fluid_bulk_modulus and porosity go together: 1/M = n / K_f + (alpha - n)(1 - alpha) / "
         "K, K the skeleton's bulk modulus");
  if (m.has("porosity")) {
    const Item n_item = m["porosity"];
    const double n = number(n_item);
    if (!(n > 0 && n < 1))
      fail(n_item, "must be in (0, 1) (got " + shown(n_item.node.Scalar()) + ")");
    const double K_f = positive(m["fluid_bulk_modulus"]);
    const double alpha = f.biot_coefficient;
    const double E = number(m["youngs_modulus"]), nu = number(m["poisson_ratio"]);
    const double K = E / (3.0 * (1.0 - 2.0 * nu));
    f.inverse_biot_modulus = n / K_f + (alpha - n) * (1.0 - alpha) / K;
    if (!(f.inverse_biot_modulus > 0))
      fail(n_item, "with this porosity and biot_coefficient the storage 1/M = n / K_f + "
                   "(alpha - n)(1 - alpha) / K is not positive; the porosity cannot exceed "
                   "alpha");
  }
  return f;
}

std::optional<double> Validator::saturated_density(const Map& m, const Vec3& gravity) const {
  if (m.has("saturated_density") && m.has("saturated_unit_weight"))
    fail(m.key("saturated_unit_weight"), "give either saturated_density (kg/m^3) or "
                                         "saturated_unit_weight (N/m^3), not both");
  if (m.has("saturated_density"))
    return positive(m["saturated_density"]);
  if (!m.has("saturated_unit_weight"))
    return std::nullopt;
  const double weight = positive(m["saturated_unit_weight"]);
  if (gravity.norm() == 0.0)
    fail(m["saturated_unit_weight"], "saturated_unit_weight needs gravity; give "
                                     "saturated_density in kg/m^3 instead, or the case's gravity");
  return weight / gravity.norm();
}

} // namespace talus::detail
