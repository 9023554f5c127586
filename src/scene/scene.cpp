#include "talus/scene/scene.hpp"

#include "talus/core/errors.hpp"
#include "talus/core/expression.hpp"
#include "talus/scene/body_geometry.hpp"
#include "talus/scene/splitting.hpp"

#include "load_reach.hpp"
#include "scene_water.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <limits>
#include <random>

namespace talus {

namespace {

/// Calls f(index) for every multi-index with first[d] <= index[d] < last[d], x fastest.
template <int Dim, class F>
void for_each_index(const std::array<Index, Dim>& first, const std::array<Index, Dim>& last,
                    F&& f) {
  for (int d = 0; d < Dim; ++d)
    if (first[d] >= last[d])
      return;
  std::array<Index, Dim> index = first;
  while (true) {
    f(index);
    int d = 0;
    while (d < Dim && ++index[d] == last[d]) {
      index[d] = first[d];
      ++d;
    }
    if (d == Dim)
      return;
  }
}

/// The centre of lattice cell `index` of spacing `spacing` from `origin`.
template <int Dim>
Vec<Dim> lattice_centre(const Vec<Dim>& origin, double spacing,
                        const std::array<Index, Dim>& index) {
  Vec<Dim> x;
  for (int d = 0; d < Dim; ++d)
    x[d] = origin[d] + spacing * (static_cast<double>(index[d]) + 0.5);
  return x;
}

// The cell-centred lattice of the sub-cells of spacing h / n (n per direction) that covers
// [lo, hi], aligned with the grid and shifted by `offset` spacings; f(site, spacing) for each
// sub-cell centre.
template <int Dim, class F>
void for_each_lattice_point(const Grid<Dim>& grid, const Vec<Dim>& lo, const Vec<Dim>& hi, int n,
                            const Vec<Dim>& offset, F&& f) {
  const double spacing = grid.cell_size() / n;
  const Vec<Dim> origin = grid.origin() + spacing * offset;
  std::array<Index, Dim> first{}, last{};
  for (int d = 0; d < Dim; ++d) {
    first[d] = static_cast<Index>(std::floor((lo[d] - origin[d]) / spacing));
    last[d] = static_cast<Index>(std::ceil((hi[d] - origin[d]) / spacing));
  }
  for_each_index<Dim>(first, last, [&](const std::array<Index, Dim>& index) {
    f(lattice_centre<Dim>(origin, spacing, index), spacing);
  });
}

template <int Dim> bool in_refine_box(const BodySpec::Refine& refine, const Vec<Dim>& q) {
  return std::any_of(refine.boxes.begin(), refine.boxes.end(), [&](const auto& b) {
    return (q.array() >= head<Dim>(b.min).array()).all() &&
           (q.array() <= head<Dim>(b.max).array()).all();
  });
}

// The body's lattice sites: particles_per_cell per direction in every grid cell, or
// refine.particles_per_cell in the cells whose centre lies in a refine box (talus adapt). The
// uniform lattice is laid out over the whole bounding box at once (the historical order of
// the points); a refined body cell by cell, each cell's sub-lattice shifted by the placement
// offset in its own spacing.
template <int Dim, class F>
void for_each_body_site(const Grid<Dim>& grid, const BodySpec& body, F&& f) {
  Vec3 lo3, hi3;
  bounding_box(body, Dim, lo3, hi3);
  const Vec<Dim> lo = head<Dim>(lo3), hi = head<Dim>(hi3);
  const Vec<Dim> offset = head<Dim>(body.placement.offset);
  if (!body.refine) {
    for_each_lattice_point<Dim>(grid, lo, hi, body.particles_per_cell, offset, f);
    return;
  }
  const double h = grid.cell_size();
  const Vec<Dim> origin = grid.origin();
  std::array<Index, Dim> first{}, last{};
  for (int d = 0; d < Dim; ++d) {
    first[d] = static_cast<Index>(std::floor((lo[d] - origin[d]) / h));
    last[d] = static_cast<Index>(std::ceil((hi[d] - origin[d]) / h));
  }
  for_each_index<Dim>(first, last, [&](const std::array<Index, Dim>& cell) {
    const Index n = in_refine_box<Dim>(*body.refine, lattice_centre<Dim>(origin, h, cell))
                        ? body.refine->particles_per_cell
                        : body.particles_per_cell;
    const double spacing = h / static_cast<double>(n);
    const Vec<Dim> shifted = origin + spacing * offset;
    std::array<Index, Dim> sub_first{}, sub_last{};
    for (int d = 0; d < Dim; ++d) {
      sub_first[d] = cell[d] * n;
      sub_last[d] = sub_first[d] + n;
    }
    for_each_index<Dim>(sub_first, sub_last, [&](const std::array<Index, Dim>& sub) {
      f(lattice_centre<Dim>(shifted, spacing, sub), spacing);
    });
  });
}

// APIC carries the velocity gradient C_p = grad v with every point. It starts as the gradient of
// the body's initial velocity field, so that the first transfer is as exact as the later ones:
// a spin started with C_p = 0 is projected like FLIP on its first step, inexactly at the edge,
// which shook the rigid-rotation disc to 5x its centrifugal stress. Expressions are
// differentiated by central differences a thousandth of a cell wide (truncation error
// 1e-7 h^2 |v'''|, round-off 1e-13 |v| / h).
template <int Dim>
void set_initial_affine_velocity(Scene<Dim>& scene, const BodySpec& body,
                                 const std::vector<Index>& created) {
  auto& P = scene.particles;
  P.affine_velocity.resize(static_cast<std::size_t>(P.size()), Mat<Dim>::Zero());
  Mat<Dim> spin = Mat<Dim>::Zero();
  spin(0, 1) = -body.angular_velocity; // a 3D body has no angular_velocity (the reader)
  spin(1, 0) = body.angular_velocity;
  for (Index p : created)
    P.affine_velocity[static_cast<std::size_t>(p)] = spin;
  const double delta = 1e-3 * scene.grid.cell_size();
  for (int d = 0; d < Dim; ++d) {
    const std::string& text = body.velocity_expression[static_cast<std::size_t>(d)];
    if (text.empty())
      continue;
    const PositionExpression velocity(text, Dim);
    for (Index p : created) {
      const Vec3 x = padded<Dim>(P.x[static_cast<std::size_t>(p)]);
      Vec<Dim> gradient;
      for (int a = 0; a < Dim; ++a) {
        Vec3 step = Vec3::Zero();
        step[a] = delta;
        gradient[a] = (velocity(x + step) - velocity(x - step)) / (2 * delta);
      }
      if (!gradient.allFinite())
        throw InputError(body.where,
                         fmt::format("velocity expression '{}' has no finite gradient at "
                                     "({:g}, {:g}, {:g}), which transfer: apic needs",
                                     text, x.x(), x.y(), x.z()));
      P.affine_velocity[static_cast<std::size_t>(p)].row(d) += gradient.transpose();
    }
  }
}

// Fills the particles of one body: one point at every lattice site (for_each_body_site) that
// lies inside the body. The placement jitter then moves each kept point within its own lattice
// cell, so a rectangle aligned with the lattice keeps all its points inside; volumes stay
// spacing^Dim (the jitter perturbs the quadrature points, not the quadrature weights).
// `lattice` receives each new point's unjittered lattice position (tractions find the body's
// outermost lattice row or column from it).
template <int Dim>
void add_body(Scene<Dim>& scene, const BodySpec& body, int body_index,
              std::vector<Vec<Dim>>& lattice) {
  const auto& grid = scene.grid;
  const MaterialSpec& mat = scene.spec.materials[static_cast<std::size_t>(body.material_index)];
  const std::optional<WaterTable> water = WaterTable::of(scene.spec);
  auto& P = scene.particles;
  const bool axisymmetric = scene.spec.geometry == Geometry::Axisymmetric;
  std::vector<Index> created;
  // A fixed generator and distribution arithmetic of our own: std::uniform_real_distribution is
  // implementation-defined, and the same seed must give the same points on every platform (so
  // the components are drawn in a fixed order, x first, not as function arguments, whose
  // order of evaluation C++ leaves open).
  std::mt19937 random(body.placement.seed);
  auto uniform = [&random] {
    return 2.0 * static_cast<double>(random() - std::mt19937::min()) /
               static_cast<double>(std::mt19937::max() - std::mt19937::min()) -
           1.0;
  };
  for_each_body_site<Dim>(grid, body, [&](const Vec<Dim>& site, double spacing) {
    if (!inside_body(body, padded<Dim>(site)) || !grid.inside(site))
      return;
    Vec<Dim> x = site;
    if (body.placement.jitter > 0) {
      Vec<Dim> shift;
      for (int d = 0; d < Dim; ++d)
        shift[d] = uniform();
      const Vec<Dim> moved = x + body.placement.jitter * spacing * shift;
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
    // Axisymmetry: the ring the voxel sweeps, per radian (Pappus: its area times the radius
    // of its centroid, the lattice site).
    P.volume0[s] = std::pow(spacing, Dim) * (axisymmetric ? site[0] : 1.0);
    P.volume[s] = P.volume0[s];
    P.mass[s] = point_density<Dim>(mat, water, x) * P.volume0[s];
    P.half_size0[s] = Vec<Dim>::Constant(0.5 * spacing);
    P.material[s] = body.material_index;
    P.body[s] = body_index;
    P.v[s] = head<Dim>(body.velocity);
  });
  if (created.empty())
    throw InputError(body.where, fmt::format("body '{}' contains no material point at cell size "
                                             "{:g} with {} particles per cell; refine the grid",
                                             body.name, grid.cell_size(), body.particles_per_cell));
  for (int d = 0; d < Dim; ++d) {
    if (body.velocity_expression[static_cast<std::size_t>(d)].empty())
      continue;
    try {
      const PositionExpression velocity(body.velocity_expression[static_cast<std::size_t>(d)], Dim);
      for (Index p : created) {
        const Vec3 x = padded<Dim>(P.x[static_cast<std::size_t>(p)]);
        const double value = velocity(x);
        if (!std::isfinite(value))
          throw std::invalid_argument(fmt::format(
              "velocity expression '{}' is {} at {}, the position of a point of body '{}'",
              body.velocity_expression[static_cast<std::size_t>(d)],
              std::isnan(value) ? "not a number (NaN)" : "infinite",
              Dim == 3 ? fmt::format("({:g}, {:g}, {:g})", x.x(), x.y(), x.z())
                       : fmt::format("({:g}, {:g})", x.x(), x.y()),
              body.name));
        P.v[static_cast<std::size_t>(p)][d] = value;
      }
    } catch (const std::invalid_argument& e) {
      throw InputError(body.velocity_where[static_cast<std::size_t>(d)], e.what());
    }
  }
  if (body.angular_velocity != 0.0) {
    // Rigid spin about the centroid of the generated points: v = v0 + omega x (x - c) (2D).
    Vec<Dim> c = Vec<Dim>::Zero();
    double m = 0;
    for (Index p : created) {
      c += P.mass[static_cast<std::size_t>(p)] * P.x[static_cast<std::size_t>(p)];
      m += P.mass[static_cast<std::size_t>(p)];
    }
    c /= m;
    for (Index p : created) {
      const Vec<Dim> r = P.x[static_cast<std::size_t>(p)] - c;
      P.v[static_cast<std::size_t>(p)][0] -= body.angular_velocity * r[1];
      P.v[static_cast<std::size_t>(p)][1] += body.angular_velocity * r[0];
    }
  }
  if (scene.spec.solver.transfer == TransferScheme::Apic)
    set_initial_affine_velocity<Dim>(scene, body, created);
}

template <int Dim> Index nearest_particle(const Particles<Dim>& P, const Vec3& q3) {
  const Vec<Dim> q = head<Dim>(q3);
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

template <int Dim> void apply_tractions(Scene<Dim>& scene, const std::vector<Vec<Dim>>& lattice) {
  auto& P = scene.particles;
  for (const TractionSpec& t : scene.spec.tractions) {
    // The outermost lattice layer of the body on the given side carries the traction; each
    // point takes the share of the side its voxel covers. Found and placed on the lattice
    // sites, so a jittered point still loads its lattice voxel's face.
    const int axis = face_axis(t.side);
    const bool upper = face_is_upper(t.side);
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
      SurfaceLoad<Dim> load;
      load.particle = p;
      load.offset = lattice[s] - P.x[s];
      load.offset[axis] += (upper ? 1.0 : -1.0) * P.half_size0[s][axis];
      // The voxel face's length (2D), area (3D), or per radian the area of the ring it sweeps
      // (axisymmetry: its length times the radius of its midpoint).
      double face = 1.0;
      for (int d = 0; d < Dim; ++d)
        if (d != axis)
          face *= 2.0 * P.half_size0[s][d];
      if (scene.spec.geometry == Geometry::Axisymmetric)
        face *= P.x[s][0] + load.offset[0];
      load.force = head<Dim>(t.traction) * face;
      // Only an implicit analysis has a load factor; explicit loads are always in full.
      load.constant = t.constant && scene.spec.analysis != AnalysisType::Explicit;
      scene.surface_loads.push_back(load);
    }
  }
}

// Geostatic or uniform initial stresses of the bodies that ask for one: the particles' stress
// and the elastic strain their material starts from. Geostatic: the vertical axis is y.
template <int Dim> void apply_initial_stress(Scene<Dim>& scene) {
  const CaseSpec& spec = scene.spec;
  const std::optional<WaterTable> water = WaterTable::of(spec);
  auto& P = scene.particles;
  for (std::size_t b = 0; b < spec.bodies.size(); ++b) {
    const BodySpec& body = spec.bodies[b];
    if (!body.initial_stress)
      continue;
    const auto& init = *body.initial_stress;
    const MaterialSpec& material = spec.materials[static_cast<std::size_t>(body.material_index)];
    const double nu = material.poisson_ratio;
    const double k0 = init.k0.value_or(nu / (1.0 - nu));
    // The material starts from the effective stress; the points carry the total one.
    std::vector<Index> ids;
    for (Index p = 0; p < P.size(); ++p) {
      const auto s = static_cast<std::size_t>(p);
      if (P.body[s] != static_cast<int>(b))
        continue;
      ids.push_back(p);
      double u = water ? water->pore_pressure<Dim>(P.x[s]) : 0.0;
      if (init.kind == BodySpec::InitialStress::Kind::Uniform)
        P.stress[s] = init.stress + u * Mat3::Identity();
      else
        P.stress[s] = geostatic_effective_stress<Dim>(material, k0, init.surface,
                                                      spec.gravity.norm(), water, P.x[s], u);
      if (water)
        P.pore_pressure[s] = u;
    }
    try {
      scene.materials[static_cast<std::size_t>(body.material_index)]->set_initial_stress(ids,
                                                                                         P.stress);
    } catch (const InputError& e) {
      throw InputError(init.where, e.detail());
    }
    if (water)
      for (const Index p : ids)
        P.stress[static_cast<std::size_t>(p)].diagonal().array() -=
            P.pore_pressure[static_cast<std::size_t>(p)];
  }
}

} // namespace

template <int Dim> Scene<Dim> build_scene(const CaseSpec& spec) {
  Scene<Dim> scene;
  scene.spec = spec;
  const auto& g = spec.grid;
  std::array<Index, Dim> cells{};
  for (int d = 0; d < Dim; ++d)
    cells[d] = static_cast<Index>(std::llround(g.extent[d] / g.cell_size));
  scene.grid = Grid<Dim>(head<Dim>(g.origin), g.cell_size, cells);
  scene.decomposition =
      std::make_shared<const Decomposition<Dim>>(Decomposition<Dim>::single(scene.grid));

  for (const MaterialSpec& m : spec.materials)
    scene.materials.push_back(make_material(m));
  std::vector<Vec<Dim>> lattice;
  for (std::size_t b = 0; b < spec.bodies.size(); ++b)
    add_body<Dim>(scene, spec.bodies[b], static_cast<int>(b), lattice);

  scene.particles_of_material.resize(spec.materials.size());
  for (Index p = 0; p < scene.particles.size(); ++p)
    scene
        .particles_of_material[static_cast<std::size_t>(
            scene.particles.material[static_cast<std::size_t>(p)])]
        .push_back(p);

  scene.water = PoreWater::of(spec);
  // The pore pressure the points' stress holds: none until an initial stress or a solver
  // puts it there.
  if (spec.water)
    scene.particles.pore_pressure.assign(static_cast<std::size_t>(scene.particles.size()), 0.0);
  apply_initial_stress<Dim>(scene);
  enable_splitting(scene);

  for (const PointLoadSpec& load : spec.point_loads) {
    const Index p = nearest_particle<Dim>(scene.particles, load.point);
    scene.particles.external_force[static_cast<std::size_t>(p)] += head<Dim>(load.force);
  }
  apply_tractions<Dim>(scene, lattice);
  scene.face_conditions =
      FaceConditions<Dim>(scene.grid, spec.boundaries, spec.geometry == Geometry::Axisymmetric);
  place_prescribed_boxes<Dim>(scene, 0.0);
  check_loads_reach_material<Dim>(scene);
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
      p = nearest_particle<Dim>(scene.particles, *probe.point);
    }
    scene.probe_particles.push_back(p);
    scene.probe_names.push_back(probe.name);
  }
  return scene;
}

template Scene<2> build_scene<2>(const CaseSpec&);
template Scene<3> build_scene<3>(const CaseSpec&);

} // namespace talus
