// The output and probes sections of a case file.
#include "validator.hpp"

namespace talus::detail {

OutputSpec default_output(bool any_plastic, bool water) {
  OutputSpec o;
  if (any_plastic)
    o.fields.push_back(OutputField::PlasticStrain);
  if (water) {
    o.fields.push_back(OutputField::PorePressure);
    o.fields.push_back(OutputField::EffectiveStress);
  }
  return o;
}

OutputSpec Validator::output(const Item& it, bool any_plastic, bool water) const {
  const Map m(*this, it,
              {"every_steps", "every_time", "fields", "stress_recovery", "voxels", "pattern_size",
               "checkpoint"});
  OutputSpec o = default_output(any_plastic, water);
  if (m.has("checkpoint")) {
    const Map c(*this, m["checkpoint"], {"every_steps", "every_seconds"});
    CheckpointSpec spec;
    if (c.has("every_steps"))
      spec.every_steps = count(c["every_steps"]);
    if (c.has("every_seconds"))
      spec.every_seconds = positive(c["every_seconds"]);
    if (!spec.every_steps && !spec.every_seconds)
      fail(c.self(), "give 'every_steps', 'every_seconds' or both");
    o.checkpoint = spec;
  }
  if (m.has("every_steps"))
    o.every_steps = count(m["every_steps"]);
  if (m.has("every_time"))
    o.every_time = positive(m["every_time"]);
  if (o.every_steps && o.every_time)
    fail(m.key("every_time"), "give at most one of 'every_steps' and 'every_time'");
  if (m.has("fields")) {
    o.fields.clear();
    for (const Item& f : list(m["fields"])) {
      const OutputField field = choice(f, output_field_choices());
      if (std::find(o.fields.begin(), o.fields.end(), field) != o.fields.end())
        fail(f, "field '" + shown(f.node.Scalar()) + "' is listed twice");
      if ((field == OutputField::PorePressure || field == OutputField::EffectiveStress) && !water)
        fail(f, "field '" + shown(f.node.Scalar()) + "' needs a water section");
      if (field == OutputField::PlasticStrain && !any_plastic)
        fail(f, "field 'plastic_strain' needs an elasto-plastic material (von_mises, tresca, "
                "mohr_coulomb, drucker_prager); every material of this case is elastic");
      o.fields.push_back(field);
    }
  }
  if (m.has("stress_recovery"))
    o.stress_recovery = boolean(m["stress_recovery"]);
  if (m.has("voxels"))
    o.voxels = boolean(m["voxels"]);
  if (m.has("pattern_size")) {
    o.pattern_size = positive(m["pattern_size"]);
    if (!o.voxels)
      fail(m.key("pattern_size"), "'pattern_size' colours the voxels; it needs 'voxels: true'");
  }
  return o;
}

std::vector<ProbeSpec> Validator::probes(const Item& it, const GridSpec& grid) const {
  std::vector<ProbeSpec> out;
  UniqueNames names(*this, "probe");
  for (const Item& item : list(it)) {
    const Map m(*this, item, {"name", "point", "particle"});
    ProbeSpec p;
    p.where = locate(m.self());
    const Item name_item = m.required("name");
    p.name = name(name_item);
    column_name(name_item, p.name);
    names.add(p.name, name_item, item.path);
    if (m.has("point") && m.has("particle"))
      fail(m.key("particle"), "give exactly one of 'point' and 'particle', not both");
    if (m.has("point")) {
      p.point = point(m["point"]);
      if (!inside_grid(*p.point, grid))
        fail(m["point"], "probe point " + vec(*p.point, dimension_) + " lies outside the grid; " +
                             grid_box(grid));
    } else if (m.has("particle")) {
      const Item particle = m["particle"];
      p.particle = integer(particle);
      p.particle_where = locate(particle);
      if (*p.particle < 0)
        fail(particle, "must be an integer >= 0 (got " + shown(particle.node.Scalar()) + ")");
    } else {
      fail(m.self(), "missing required key 'point' or 'particle' (give exactly one)");
    }
    out.push_back(std::move(p));
  }
  return out;
}

} // namespace talus::detail
