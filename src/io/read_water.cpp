// The water section of a case file and the materials' saturated weights (docs/case-format.md,
// water).
#include "validator.hpp"

namespace talus::detail {

WaterSpec Validator::water(const Item& it, const CaseSpec& spec) const {
  const Map m(*this, it, {"unit_weight", "level", "phreatic"});
  WaterSpec w;
  w.where = locate(m.self());
  if (m.has("unit_weight"))
    w.unit_weight = positive(m["unit_weight"]);
  if (m.has("level") == m.has("phreatic"))
    fail(m.has("level") ? m.key("phreatic") : m.self(),
         "give the phreatic surface once: level: y (a level water table) or phreatic: [[x, y], "
         "...] (a polyline of ascending x)");
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
