#include "talus/core/scene.hpp"

#include "talus/core/body_geometry.hpp"
#include "talus/core/errors.hpp"
#include "talus/core/expression.hpp"
#include "talus/core/splitting.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <limits>
#include <random>

namespace talus {

const char* face_name(int face) {
  static const char* names[] = {"x_min", "x_max", "y_min", "y_max"};
  return names[face];
}

namespace {

// The cell-centred lattice of the sub-cells of spacing h / n (n per direction) that covers
// [lo, hi], aligned with the grid and shifted by `offset` spacings; f(site, spacing) for each
// sub-cell centre.
template <class F>
void for_each_lattice_point(const Grid<2>& grid, const Vec2& lo, const Vec2& hi, int n,
                            const Vec2& offset, F&& f) {
  const double spacing = grid.cell_size() / n;
  const Vec2 origin = grid.origin() + spacing * offset;
  std::array<Index, 2> first{}, last{};
  for (int d = 0; d < 2; ++d) {
    first[d] = static_cast<Index>(std::floor((lo[d] - origin[d]) / spacing));
    last[d] = static_cast<Index>(std::ceil((hi[d] - origin[d]) / spacing));
  }
  for (Index j = first[1]; j < last[1]; ++j)
    for (Index i = first[0]; i < last[0]; ++i)
      f(origin + spacing * Vec2(static_cast<double>(i) + 0.5, static_cast<double>(j) + 0.5),
        spacing);
}

bool in_refine_box(const BodySpec::Refine& refine, const Vec2& q) {
  return std::any_of(refine.boxes.begin(), refine.boxes.end(), [&](const auto& b) {
    return q.x() >= b[0] && q.x() <= b[2] && q.y() >= b[1] && q.y() <= b[3];
  });
}

// The body's lattice sites: particles_per_cell per direction in every grid cell, or
// refine.particles_per_cell in the cells whose centre lies in a refine box (talus adapt). The
// uniform lattice is laid out over the whole bounding box at once (the historical order of
// the points); a refined body cell by cell, each cell's sub-lattice shifted by the placement
// offset in its own spacing.
template <class F> void for_each_body_site(const Grid<2>& grid, const BodySpec& body, F&& f) {
  Vec2 lo, hi;
  bounding_box(body, lo, hi);
  const Vec2& offset = body.placement.offset;
  if (!body.refine) {
    for_each_lattice_point(grid, lo, hi, body.particles_per_cell, offset, f);
    return;
  }
  const double h = grid.cell_size();
  const Vec2 origin = grid.origin();
  std::array<Index, 2> first{}, last{};
  for (int d = 0; d < 2; ++d) {
    first[d] = static_cast<Index>(std::floor((lo[d] - origin[d]) / h));
    last[d] = static_cast<Index>(std::ceil((hi[d] - origin[d]) / h));
  }
  for (Index cj = first[1]; cj < last[1]; ++cj)
    for (Index ci = first[0]; ci < last[0]; ++ci) {
      const Vec2 centre =
          origin + h * Vec2(static_cast<double>(ci) + 0.5, static_cast<double>(cj) + 0.5);
      const Index n = in_refine_box(*body.refine, centre) ? body.refine->particles_per_cell
                                                          : body.particles_per_cell;
      const double spacing = h / static_cast<double>(n);
      const Vec2 shifted = origin + spacing * offset;
      for (Index sj = 0; sj < n; ++sj)
        for (Index si = 0; si < n; ++si)
          f(shifted + spacing * Vec2(static_cast<double>(ci * n + si) + 0.5,
                                     static_cast<double>(cj * n + sj) + 0.5),
            spacing);
    }
}

// APIC carries the velocity gradient C_p = grad v with every point. It starts as the gradient of
// the body's initial velocity field, so that the first transfer is as exact as the later ones:
// a spin started with C_p = 0 is projected like FLIP on its first step, inexactly at the edge,
// which shook the rigid-rotation disc to 5x its centrifugal stress. Expressions are
// differentiated by central differences a thousandth of a cell wide (truncation error
// 1e-7 h^2 |v'''|, round-off 1e-13 |v| / h).
void set_initial_affine_velocity(Scene<2>& scene, const BodySpec& body,
                                 const std::vector<Index>& created) {
  auto& P = scene.particles;
  P.affine_velocity.resize(static_cast<std::size_t>(P.size()), Mat2::Zero());
  Mat2 spin;
  spin << 0.0, -body.angular_velocity, body.angular_velocity, 0.0;
  for (Index p : created)
    P.affine_velocity[static_cast<std::size_t>(p)] = spin;
  const double delta = 1e-3 * scene.grid.cell_size();
  for (int d = 0; d < 2; ++d) {
    const std::string& text = body.velocity_expression[static_cast<std::size_t>(d)];
    if (text.empty())
      continue;
    const PositionExpression velocity(text);
    for (Index p : created) {
      const Vec2& x = P.x[static_cast<std::size_t>(p)];
      const Vec2 gradient(velocity(x.x() + delta, x.y()) - velocity(x.x() - delta, x.y()),
                          velocity(x.x(), x.y() + delta) - velocity(x.x(), x.y() - delta));
      if (!gradient.allFinite())
        throw InputError(body.where,
                         fmt::format("velocity expression '{}' has no finite gradient at "
                                     "({:g}, {:g}), which transfer: apic needs",
                                     text, x.x(), x.y()));
      P.affine_velocity[static_cast<std::size_t>(p)].row(d) += gradient.transpose() / (2 * delta);
    }
  }
}

// Fills the particles of one body: one point at every lattice site (for_each_body_site) that
// lies inside the body. The placement jitter then moves each kept point within its own lattice
// cell, so a rectangle aligned with the lattice keeps all its points inside; volumes stay
// spacing^2 (the jitter perturbs the quadrature points, not the quadrature weights).
// `lattice` receives each new point's unjittered lattice position (tractions find the body's
// outermost lattice row or column from it).
void add_body(Scene<2>& scene, const BodySpec& body, int body_index, std::vector<Vec2>& lattice) {
  const auto& grid = scene.grid;
  const MaterialSpec& mat = scene.spec.materials[static_cast<std::size_t>(body.material_index)];
  auto& P = scene.particles;
  std::vector<Index> created;
  // A fixed generator and distribution arithmetic of our own: std::uniform_real_distribution is
  // implementation-defined, and the same seed must give the same points on every platform.
  std::mt19937 random(body.placement.seed);
  auto uniform = [&random] {
    return 2.0 * static_cast<double>(random() - std::mt19937::min()) /
               static_cast<double>(std::mt19937::max() - std::mt19937::min()) -
           1.0;
  };
  for_each_body_site(grid, body, [&](const Vec2& site, double spacing) {
    if (!inside_body(body, site) || !grid.inside(site))
      return;
    Vec2 x = site;
    if (body.placement.jitter > 0) {
      const Vec2 moved = x + body.placement.jitter * spacing * Vec2(uniform(), uniform());
      // Only a lattice cell cut by the grid boundary can send a point out; it stays put.
      if (grid.inside(moved))
        x = moved;
    }
    lattice.push_back(site);
    created.push_back(P.size());
    const Index p = P.size();
    P.resize(p + 1);
    const auto s = static_cast<std::size_t>(p);
    P.x[s] = x;
    P.x0[s] = x;
    P.volume0[s] = spacing * spacing;
    P.volume[s] = P.volume0[s];
    P.mass[s] = mat.density * P.volume0[s];
    P.half_size0[s] = Vec2::Constant(0.5 * spacing);
    P.material[s] = body.material_index;
    P.body[s] = body_index;
    P.v[s] = body.velocity;
  });
  if (created.empty())
    throw InputError(body.where, fmt::format("body '{}' contains no material point at cell size "
                                             "{:g} with {} particles per cell; refine the grid",
                                             body.name, grid.cell_size(), body.particles_per_cell));
  for (int d = 0; d < 2; ++d) {
    if (body.velocity_expression[static_cast<std::size_t>(d)].empty())
      continue;
    try {
      const PositionExpression velocity(body.velocity_expression[static_cast<std::size_t>(d)]);
      for (Index p : created) {
        const Vec2& x = P.x[static_cast<std::size_t>(p)];
        const double value = velocity(x.x(), x.y());
        if (!std::isfinite(value))
          throw std::invalid_argument(fmt::format(
              "velocity expression '{}' is {} at ({:g}, {:g}), the position of a point of body "
              "'{}'",
              body.velocity_expression[static_cast<std::size_t>(d)],
              std::isnan(value) ? "not a number (NaN)" : "infinite", x.x(), x.y(), body.name));
        P.v[static_cast<std::size_t>(p)][d] = value;
      }
    } catch (const std::invalid_argument& e) {
      throw InputError(body.velocity_where[static_cast<std::size_t>(d)], e.what());
    }
  }
  if (body.angular_velocity != 0.0) {
    // Rigid spin about the centroid of the generated points: v = v0 + omega x (x - c).
    Vec2 c = Vec2::Zero();
    double m = 0;
    for (Index p : created) {
      c += P.mass[static_cast<std::size_t>(p)] * P.x[static_cast<std::size_t>(p)];
      m += P.mass[static_cast<std::size_t>(p)];
    }
    c /= m;
    for (Index p : created) {
      const Vec2 r = P.x[static_cast<std::size_t>(p)] - c;
      P.v[static_cast<std::size_t>(p)] += body.angular_velocity * Vec2(-r.y(), r.x());
    }
  }
  if (scene.spec.solver.transfer == TransferScheme::Apic)
    set_initial_affine_velocity(scene, body, created);
}

Index nearest_particle(const Particles<2>& P, const Vec2& q) {
  Index best = -1;
  double best_d = std::numeric_limits<double>::infinity();
  for (Index p = 0; p < P.size(); ++p) {
    const double d = (P.x[static_cast<std::size_t>(p)] - q).squaredNorm();
    if (d < best_d) {
      best_d = d;
      best = p;
    }
  }
  return best;
}

void apply_tractions(Scene<2>& scene, const std::vector<Vec2>& lattice) {
  auto& P = scene.particles;
  for (const TractionSpec& t : scene.spec.tractions) {
    // The outermost lattice row or column of the body on the given side carries the traction;
    // each point takes the share of the side length its voxel covers. Found and placed on the
    // lattice sites, so a jittered point still loads its lattice voxel's face.
    const int axis = (t.side == Side::Left || t.side == Side::Right) ? 0 : 1;
    const bool upper = (t.side == Side::Right || t.side == Side::Top);
    double extreme =
        upper ? -std::numeric_limits<double>::infinity() : std::numeric_limits<double>::infinity();
    for (Index p = 0; p < P.size(); ++p) {
      const auto s = static_cast<std::size_t>(p);
      if (P.body[s] != t.body_index)
        continue;
      extreme = upper ? std::max(extreme, lattice[s][axis]) : std::min(extreme, lattice[s][axis]);
    }
    for (Index p = 0; p < P.size(); ++p) {
      const auto s = static_cast<std::size_t>(p);
      if (P.body[s] != t.body_index)
        continue;
      const double tol = 1e-6 * P.half_size0[s][axis];
      if (std::abs(lattice[s][axis] - extreme) > tol)
        continue;
      SurfaceLoad load;
      load.particle = p;
      load.offset = lattice[s] - P.x[s];
      load.offset[axis] += (upper ? 1.0 : -1.0) * P.half_size0[s][axis];
      load.force = t.traction * (2.0 * P.half_size0[s][1 - axis]);
      // Only an implicit analysis has a load factor; explicit loads are always in full.
      load.constant = t.constant && scene.spec.analysis != AnalysisType::Explicit;
      scene.surface_loads.push_back(load);
    }
  }
}

void constrain_faces(Scene<2>& scene) {
  const auto& g = scene.grid;
  const auto& bc = scene.spec.boundaries;
  scene.constrained.assign(static_cast<std::size_t>(g.node_count()), 0);
  scene.component_face.assign(2 * static_cast<std::size_t>(g.node_count()), -1);
  auto mask_of = [](FaceCondition c, int normal_axis) -> std::uint8_t {
    switch (c) {
    case FaceCondition::Free:
      return 0;
    case FaceCondition::Fixed:
      return 0b11;
    case FaceCondition::Roller:
      return static_cast<std::uint8_t>(1u << normal_axis);
    }
    return 0;
  };
  const FaceCondition conds[kFaceCount] = {bc.x_min, bc.x_max, bc.y_min, bc.y_max};
  for (Index id = 0; id < g.node_count(); ++id) {
    const auto ijk = g.node_ijk(id);
    for (int face = 0; face < kFaceCount; ++face) {
      const int axis = face / 2;
      const bool upper = face % 2 == 1;
      // The boundary node and the ghost node behind it (inside the wall) share the condition.
      const bool on_face = upper ? ijk[axis] >= g.cells(axis) : ijk[axis] <= 0;
      if (!on_face || conds[face] == FaceCondition::Free)
        continue;
      const std::uint8_t mask = mask_of(conds[face], axis);
      scene.constrained[static_cast<std::size_t>(id)] |= mask;
      for (int d = 0; d < 2; ++d) {
        auto& owner = scene.component_face[2 * static_cast<std::size_t>(id) + d];
        if ((mask & (1u << d)) && (owner < 0 || d == axis))
          owner = static_cast<std::int8_t>(face);
      }
    }
  }
}

// Geostatic or uniform initial stresses of the bodies that ask for one: the particles' stress
// and the elastic strain their material starts from.
void apply_initial_stress(Scene<2>& scene) {
  const CaseSpec& spec = scene.spec;
  auto& P = scene.particles;
  for (std::size_t b = 0; b < spec.bodies.size(); ++b) {
    const BodySpec& body = spec.bodies[b];
    if (!body.initial_stress)
      continue;
    const auto& init = *body.initial_stress;
    const MaterialSpec& material = spec.materials[static_cast<std::size_t>(body.material_index)];
    const double nu = material.poisson_ratio;
    const double k0 = init.k0.value_or(nu / (1.0 - nu));
    const double unit_weight = material.density * spec.gravity.norm();
    std::vector<Index> ids;
    for (Index p = 0; p < P.size(); ++p) {
      const auto s = static_cast<std::size_t>(p);
      if (P.body[s] != static_cast<int>(b))
        continue;
      ids.push_back(p);
      Mat3 sigma = Mat3::Zero();
      if (init.kind == BodySpec::InitialStress::Kind::Uniform) {
        sigma(0, 0) = init.stress[0];
        sigma(1, 1) = init.stress[1];
        sigma(0, 1) = sigma(1, 0) = init.stress[2];
        sigma(2, 2) = init.stress[3];
      } else {
        const double vertical = -unit_weight * std::max(0.0, init.surface - P.x[s].y());
        sigma(1, 1) = vertical;
        sigma(0, 0) = sigma(2, 2) = k0 * vertical;
      }
      P.stress[s] = sigma;
    }
    try {
      scene.materials[static_cast<std::size_t>(body.material_index)]->set_initial_stress(ids,
                                                                                         P.stress);
    } catch (const InputError& e) {
      throw InputError(init.where, e.detail());
    }
  }
}

} // namespace

void locate_prescribed_nodes(Scene<2>& scene, double ramp) {
  const CaseSpec& spec = scene.spec;
  scene.node_prescribed.assign(static_cast<std::size_t>(scene.grid.node_count()), -1);
  const double tol = 1e-9 * scene.grid.cell_size();
  for (Index id = 0; id < scene.grid.node_count(); ++id) {
    const Vec2 x = scene.grid.node_position(scene.grid.node_ijk(id));
    for (std::size_t r = 0; r < spec.prescribed.size(); ++r) {
      const PrescribedSpec& box = spec.prescribed[r];
      // The box moves in whole cells, the prescribed displacement rounded to the nearest
      // multiple of h, so that it keeps holding the same number of node layers (a box one
      // layer thick would otherwise lose its nodes as soon as it moves).
      const double h = scene.grid.cell_size();
      Vec2 shift = Vec2::Zero();
      for (int d = 0; d < 2; ++d)
        if (box.displacement[static_cast<std::size_t>(d)])
          shift[d] = h * std::round(ramp * *box.displacement[static_cast<std::size_t>(d)] / h);
      if ((x.array() >= (box.min + shift).array() - tol).all() &&
          (x.array() <= (box.max + shift).array() + tol).all()) {
        scene.node_prescribed[static_cast<std::size_t>(id)] = static_cast<std::int32_t>(r);
        break;
      }
    }
  }
}

Scene<2> build_scene(const CaseSpec& spec) {
  Scene<2> scene;
  scene.spec = spec;
  const auto& g = spec.grid;
  std::array<Index, 2> cells{};
  for (int d = 0; d < 2; ++d)
    cells[d] = static_cast<Index>(std::llround(g.extent[d] / g.cell_size));
  scene.grid = Grid<2>(g.origin, g.cell_size, cells);

  for (const MaterialSpec& m : spec.materials)
    scene.materials.push_back(make_material(m));
  std::vector<Vec2> lattice;
  for (std::size_t b = 0; b < spec.bodies.size(); ++b)
    add_body(scene, spec.bodies[b], static_cast<int>(b), lattice);

  scene.particles_of_material.resize(spec.materials.size());
  for (Index p = 0; p < scene.particles.size(); ++p)
    scene
        .particles_of_material[static_cast<std::size_t>(
            scene.particles.material[static_cast<std::size_t>(p)])]
        .push_back(p);

  apply_initial_stress(scene);
  enable_splitting(scene);

  for (const PointLoadSpec& load : spec.point_loads) {
    const Index p = nearest_particle(scene.particles, load.point);
    scene.particles.external_force[static_cast<std::size_t>(p)] += load.force;
  }
  apply_tractions(scene, lattice);
  constrain_faces(scene);

  locate_prescribed_nodes(scene, 0.0);
  for (const ProbeSpec& probe : spec.probes) {
    Index p = -1;
    if (probe.particle) {
      p = *probe.particle;
      if (p >= scene.particles.size())
        throw InputError(probe.particle_where,
                         fmt::format("probe '{}' names particle {}, but the scene has {} "
                                     "particles (0 to {})",
                                     probe.name, p, scene.particles.size(),
                                     scene.particles.size() - 1));
    } else {
      p = nearest_particle(scene.particles, *probe.point);
    }
    scene.probe_particles.push_back(p);
    scene.probe_names.push_back(probe.name);
  }
  return scene;
}

} // namespace talus
