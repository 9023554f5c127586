// The bodies section of a case file: material, velocity, placement, initial stress, splitting
// and refinement (docs/case-format.md, bodies). Shapes and their geometry: read_body_geometry.cpp.
#include "talus/scene/body_geometry.hpp"

#include "validator.hpp"

#include <cmath>
#include <numbers>

namespace talus::detail {

std::vector<BodySpec> Validator::bodies(const Item& it, const CaseSpec& spec) const {
  const std::vector<Item> items = list(it);
  if (items.empty())
    fail(it, "list at least one body");
  std::vector<std::string> material_names;
  for (const auto& mat : spec.materials)
    material_names.push_back(mat.name);

  std::vector<BodySpec> out;
  UniqueNames names(*this, "body");
  for (const Item& item : items) {
    const Map m(*this, item,
                {"name", "material", "shape", "centre", "radius", "min", "max", "vertices", "axis",
                 "z_min", "z_max", "particles_per_cell", "velocity", "angular_velocity",
                 "initial_stress", "split", "placement", "refine"});
    BodySpec b;
    b.where = locate(m.self());
    const Item name_item = m.required("name");
    b.name = name(name_item);
    names.add(b.name, name_item, item.path);

    const Item material = m.required("material");
    b.material = name(material);
    const auto found = std::find(material_names.begin(), material_names.end(), b.material);
    if (found == material_names.end()) {
      std::string what = "unknown material '" + shown(b.material) +
                         "' (defined materials: " + join(material_names) + ")";
      const std::string guess = closest_match(b.material, material_names);
      if (!guess.empty())
        what += "; did you mean '" + guess + "'?";
      fail(material, what);
    }
    b.material_index = static_cast<int>(found - material_names.begin());

    body_shape(m, b);

    if (m.has("particles_per_cell")) {
      const Item ppc = m["particles_per_cell"];
      const Index n = integer(ppc);
      if (n < 1 || n > 16)
        fail(ppc, "must be an integer from 1 to 16 (got " + shown(ppc.node.Scalar()) + ")");
      b.particles_per_cell = static_cast<int>(n);
    }
    if (m.has("velocity")) {
      const Item velocity = m["velocity"];
      position_field(velocity, b.velocity, b.velocity_expression);
      for (std::size_t d = 0; d < static_cast<std::size_t>(dimension_); ++d)
        b.velocity_where[d] =
            locate(mark_or(velocity.node[d], velocity.mark), child_path(velocity.path, d));
    }
    if (m.has("angular_velocity")) {
      if (dimension_ == 3)
        fail(m.key("angular_velocity"), "angular_velocity is a spin about z of a 2D body; a 3D "
                                        "case has no such key yet");
      if (axisymmetric_)
        fail(m.key("angular_velocity"), "angular_velocity spins a body in its plane, which an "
                                        "axisymmetric body (a ring of revolution) cannot do");
      b.angular_velocity = number(m["angular_velocity"]);
    }
    if (m.present("placement"))
      b.placement = placement(m["placement"]);

    body_inside_grid(m, b, spec.grid);
    if (axisymmetric_)
      body_off_axis(m, b);
    if (m.present("initial_stress"))
      b.initial_stress = initial_stress(m["initial_stress"], b, spec);
    if (m.present("split"))
      b.split = split(m["split"]);
    if (m.present("refine"))
      b.refine = refine(m["refine"]);
    out.push_back(std::move(b));
  }
  bodies_apart(items, out, spec.grid);
  return out;
}

BodySpec::Placement Validator::placement(const Item& it) const {
  const Map m(*this, it, {"offset", "jitter", "seed"});
  BodySpec::Placement p;
  if (m.has("offset")) {
    p.offset = point(m["offset"]);
    // Half a spacing or more would move a point into its neighbour's lattice cell.
    if (p.offset.cwiseAbs().maxCoeff() >= 0.5)
      fail(m["offset"], "each component must lie in the open interval (-0.5, 0.5) (a fraction "
                        "of the point spacing)");
  }
  if (m.has("jitter")) {
    p.jitter = number(m["jitter"]);
    if (p.jitter < 0 || p.jitter >= 0.5)
      fail(m["jitter"], "must lie in [0, 0.5) (a fraction of the point spacing, so that every "
                        "point stays in its own lattice cell)");
  }
  if (m.has("seed")) {
    const Index seed = integer(m["seed"]);
    if (seed < 0 || seed > 4294967295)
      fail(m["seed"], "must be an integer from 0 to 4294967295");
    p.seed = static_cast<unsigned>(seed);
  }
  return p;
}

BodySpec::InitialStress Validator::initial_stress(const Item& it, const BodySpec& b,
                                                  const CaseSpec& spec) const {
  const MaterialSpec& material = spec.materials[static_cast<std::size_t>(b.material_index)];
  if (!is_plastic(material.model))
    fail(it, "an initial stress needs a model with an elastic strain state (von_mises, tresca, "
             "mohr_coulomb, drucker_prager); material '" +
                 material.name + "' is elastic, its stress follows from F alone");
  const Map m(*this, it, {"type", "surface", "k0", "stress"});
  BodySpec::InitialStress s;
  using Kind = BodySpec::InitialStress::Kind;
  s.kind = choice<Kind>(m.required("type"),
                        {{"geostatic", Kind::Geostatic}, {"uniform", Kind::Uniform}});
  for (const char* key : {"surface", "k0", "stress"}) {
    const bool geostatic_key = std::string(key) != "stress";
    if (m.has(key) && geostatic_key != (s.kind == Kind::Geostatic))
      fail(m.key(key), std::string("'") + key + "' does not apply to initial stress type '" +
                           shown(m["type"].node.Scalar()) + "'");
  }
  if (s.kind == Kind::Uniform) {
    const Item stress = m.required("stress");
    const std::vector<Item> values = list(stress);
    // 2D: the in-plane components and sigma_zz; 3D: the six of the symmetric tensor.
    const std::size_t count = dimension_ == 3 ? 6 : 4;
    if (values.size() != count)
      fail(stress, dimension_ == 3 ? "give six stresses [sigma_xx, sigma_yy, sigma_zz, sigma_xy, "
                                     "sigma_yz, sigma_xz] in Pa"
                                   : "give four stresses [sigma_xx, sigma_yy, sigma_xy, sigma_zz] "
                                     "in Pa");
    std::array<double, 6> c{};
    for (std::size_t k = 0; k < count; ++k)
      c[k] = number(values[k]);
    if (dimension_ == 3)
      s.stress << c[0], c[3], c[5], c[3], c[1], c[4], c[5], c[4], c[2];
    else
      s.stress << c[0], c[2], 0, c[2], c[1], 0, 0, 0, c[3];
    s.where = locate(stress);
    return s;
  }
  if (spec.gravity.norm() == 0.0 || spec.gravity.x() != 0.0 || spec.gravity.y() > 0.0 ||
      spec.gravity.z() != 0.0)
    fail(m.self(), dimension_ == 3
                       ? "a geostatic initial stress needs gravity along -y (gravity: [0, -g, 0])"
                       : "a geostatic initial stress needs gravity along -y (gravity: [0, -g])");
  // Default surface: the body's top.
  Vec3 lo, hi;
  bounding_box(b, dimension_, lo, hi);
  s.surface = hi.y();
  if (m.has("surface"))
    s.surface = number(m["surface"]);
  s.where = locate(m.self());
  if (m.has("k0")) {
    const Item k0 = m["k0"];
    s.where = locate(k0);
    if (k0.node.IsScalar() && k0.node.Scalar() == "jaky") {
      // Jaky's (1944) K0 = 1 - sin(phi') of a normally consolidated soil.
      if (material.model != MaterialModel::MohrCoulomb &&
          material.model != MaterialModel::DruckerPrager)
        fail(k0, "k0: jaky needs a friction angle; material '" + material.name +
                     "' has none (mohr_coulomb and drucker_prager have one)");
      s.k0 = 1.0 - std::sin(material.friction_angle * std::numbers::pi / 180.0);
      if (!(*s.k0 > 0.0))
        fail(k0, "k0: jaky gives 1 - sin(phi) <= 0 for material '" + material.name + "'");
    } else {
      s.k0 = number(k0);
      if (!(*s.k0 > 0.0))
        fail(k0,
             "must be positive, or jaky for 1 - sin(phi) (got " + shown(k0.node.Scalar()) + ")");
    }
  }
  return s;
}

SplitSpec Validator::split(const Item& it) const {
  const Map m(*this, it, {"alpha", "beta", "gamma", "max_generations", "min_size"});
  SplitSpec s;
  if (m.has("alpha")) {
    const Item alpha = m["alpha"];
    s.alpha = number(alpha);
    if (!(s.alpha > 1.0))
      fail(alpha, "must be > 1: a stretch limit (got " + shown(alpha.node.Scalar()) + ")");
  }
  if (m.has("beta")) {
    const Item beta = m["beta"];
    s.beta = number(beta);
    if (!(s.beta > 0.0 && s.beta < 1.0))
      fail(beta, "must be in the open interval (0, 1): a compression limit (got " +
                     shown(beta.node.Scalar()) + ")");
  }
  if (m.has("gamma"))
    s.gamma = positive(m["gamma"]);
  if (m.has("max_generations")) {
    const Item gen = m["max_generations"];
    const Index n = integer(gen);
    // 2^30 descendants of one point is far beyond any memory; the cap keeps the count in int.
    if (n < 0 || n > 30)
      fail(gen, "must be an integer from 0 to 30 (got " + shown(gen.node.Scalar()) + ")");
    s.max_generations = static_cast<int>(n);
  }
  if (m.has("min_size")) {
    const Item size = m["min_size"];
    s.min_size = number(size);
    if (!(s.min_size >= 0.0))
      fail(size, "must be >= 0 m (got " + shown(size.node.Scalar()) + ")");
  }
  return s;
}

BodySpec::Refine Validator::refine(const Item& it) const {
  const Map m(*this, it, {"particles_per_cell", "boxes"});
  BodySpec::Refine r;
  const Item ppc = m.required("particles_per_cell");
  const Index n = integer(ppc);
  if (n < 1 || n > 16)
    fail(ppc, "must be an integer from 1 to 16 (got " + shown(ppc.node.Scalar()) + ")");
  r.particles_per_cell = static_cast<int>(n);
  const auto dims = static_cast<std::size_t>(dimension_);
  for (const Item& box : list(m.required("boxes"))) {
    const std::vector<Item> values = list(box);
    if (values.size() != 2 * dims)
      fail(box, dims == 3 ? "give a box as [x_min, y_min, z_min, x_max, y_max, z_max] in m"
                          : "give a box as [x_min, y_min, x_max, y_max] in m");
    BodySpec::Refine::Box b;
    for (std::size_t k = 0; k < dims; ++k) {
      b.min[static_cast<Eigen::Index>(k)] = number(values[k]);
      b.max[static_cast<Eigen::Index>(k)] = number(values[dims + k]);
    }
    if (!below_along_all(b.min, b.max, dimension_))
      fail(box, dims == 3 ? "a box needs x_max > x_min, y_max > y_min and z_max > z_min"
                          : "a box needs x_max > x_min and y_max > y_min");
    r.boxes.push_back(b);
  }
  return r;
}

} // namespace talus::detail
