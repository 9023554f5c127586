// The materials section of a case file (docs/case-format.md, materials).
#include "talus/material/plastic_material.hpp"
#include "validator.hpp"

namespace talus::detail {

std::vector<MaterialSpec> Validator::materials(const Item& it, const Vec3& gravity) const {
  const std::vector<Item> items = list(it);
  if (items.empty())
    fail(it, "list at least one material");
  std::vector<MaterialSpec> out;
  UniqueNames names(*this, "material");
  for (const Item& item : items) {
    const Map m(*this, item,
                {"name",
                 "model",
                 "density",
                 "unit_weight",
                 "youngs_modulus",
                 "poisson_ratio",
                 "kinematics",
                 "yield_stress",
                 "hardening_modulus",
                 "cohesion",
                 "friction_angle",
                 "dilation_angle",
                 "residual",
                 "saturated_density",
                 "saturated_unit_weight",
                 "permeability",
                 "biot_coefficient",
                 "biot_modulus",
                 "fluid_bulk_modulus",
                 "porosity"});
    MaterialSpec s;
    s.where = locate(m.self());
    const Item name_item = m.required("name");
    s.name = name(name_item);
    names.add(s.name, name_item, item.path);
    const Item model_item = m.required("model");
    s.model = choice(model_item, material_model_choices());
    s.density = density(m, gravity);
    s.saturated_density = saturated_density(m, gravity);
    s.youngs_modulus = positive(m.required("youngs_modulus"));
    const Item nu = m.required("poisson_ratio");
    s.poisson_ratio = number(nu);
    if (!(s.poisson_ratio > -1 && s.poisson_ratio < 0.5))
      fail(nu, "must be in the open interval (-1, 0.5) (got " + shown(nu.node.Scalar()) + ")");
    plastic_parameters(m, model_item, s);
    s.flow = pore_flow(m);
    out.push_back(std::move(s));
  }
  return out;
}

/// `density` (kg/m^3), or `unit_weight` (N/m^3, the geotechnical gamma) divided by the case's
/// |g|, so that rho |g| is exactly the weight given.
double Validator::density(const Map& m, const Vec3& gravity) const {
  if (m.has("density") && m.has("unit_weight"))
    fail(m.key("unit_weight"), "give either density (kg/m^3) or unit_weight (N/m^3), not both");
  if (!m.has("unit_weight")) {
    if (!m.has("density"))
      fail(m.self(), "missing required key 'density' (kg/m^3), or give 'unit_weight' (N/m^3)");
    return positive(m["density"]);
  }
  const Item gamma = m["unit_weight"];
  const double weight = positive(gamma);
  if (gravity.norm() == 0.0)
    fail(gamma, "unit_weight needs gravity (the case has none, so the weight says nothing about "
                "the mass); give density in kg/m^3 instead, or the case's gravity");
  return weight / gravity.norm();
}

void Validator::plastic_parameters(const Map& m, const Item& model_item, MaterialSpec& s) const {
  // The keys each model takes beyond the elastic ones; any other is refused by name.
  const std::vector<std::string> frictional = {"kinematics", "cohesion", "friction_angle",
                                               "dilation_angle", "residual"};
  std::vector<std::string> takes;
  switch (s.model) {
  case MaterialModel::VonMises:
    takes = {"kinematics", "yield_stress", "hardening_modulus"};
    break;
  case MaterialModel::Tresca:
    takes = {"kinematics", "cohesion"};
    break;
  case MaterialModel::MohrCoulomb:
  case MaterialModel::DruckerPrager:
    takes = frictional;
    break;
  default:
    break;
  }
  for (const char* key : {"kinematics", "yield_stress", "hardening_modulus", "cohesion",
                          "friction_angle", "dilation_angle", "residual"})
    if (m.has(key) && std::find(takes.begin(), takes.end(), key) == takes.end())
      fail(m.key(key), std::string("'") + key + "' does not apply to model '" +
                           shown(model_item.node.Scalar()) + "'" +
                           (takes.empty() ? std::string(" (an elastic model)")
                                          : " (it takes: " + join(takes) + ")"));
  if (takes.empty())
    return;
  if (m.has("kinematics"))
    s.small_strain =
        choice<bool>(m["kinematics"], {{"finite_strain", false}, {"small_strain", true}});
  if (s.model == MaterialModel::VonMises) {
    s.yield_stress = positive(m.required("yield_stress"));
    if (m.has("hardening_modulus"))
      s.hardening_modulus = number(m["hardening_modulus"]);
  } else {
    s.cohesion = number(m.required("cohesion"));
  }
  if (s.model == MaterialModel::MohrCoulomb || s.model == MaterialModel::DruckerPrager) {
    s.friction_angle = number(m.required("friction_angle"));
    if (m.has("dilation_angle"))
      s.dilation_angle = number(m["dilation_angle"]);
    if (m.present("residual")) {
      const Map r(*this, m["residual"], {"cohesion", "friction_angle", "plastic_strain"});
      s.residual =
          ResidualStrengthSpec{number(r.required("cohesion")), number(r.required("friction_angle")),
                               number(r.required("plastic_strain"))};
    }
  }
  // The model checks its own parameters (ranges, psi <= phi, ...); report at the key it names.
  try {
    make_plastic_model(s);
  } catch (const InputError& e) {
    std::string key = e.where().key_path;
    if (key == "residual.kappa")
      key = "residual.plastic_strain";
    Item at = m.self();
    if (key.rfind("residual.", 0) == 0 && m.present("residual")) {
      const Map r(*this, m["residual"], {"cohesion", "friction_angle", "plastic_strain"});
      const std::string sub = key.substr(9);
      if (r.has(sub))
        at = r[sub];
    } else if (m.has(key)) {
      at = m[key];
    }
    fail(at, e.detail());
  }
}

} // namespace talus::detail
