#pragma once
// What an implicit load step is posed on, set up once at its start (updated Lagrangian): the
// connectivity at the step's start configuration, the node masses, the unknowns (one per
// component of a node with mass that no face holds), the prescribed increments, the loads with
// the force scale Newton's tolerance is relative to, the ghost-penalty faces, and for Newmark
// the lumped mass with the projected velocity and acceleration per unknown
// (implicit_solver.cpp assembles and solves on it).
#include "talus/core/scene.hpp"
#include "talus/grid/particle_grid_map.hpp"
#include "talus/solver/ghost_penalty.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

namespace talus {

// Nodes whose mass is below this fraction of the heaviest node's carry no material in any
// meaningful sense (round-off of a support edge); their increments are held at zero. The
// threshold is deliberately tiny: holding nodes with a real share of a point's support
// stiffens the body (measured: a bent cantilever at 1 % lost 90 % of its deflection). Nodes
// with a small share are kept and stabilised by the ghost penalty (ghost_penalty.hpp).
constexpr double kImplicitTinyNodeMassFraction = 1e-10;

template <int Dim, class Shape, bool Axisymmetric> struct ImplicitStepSetup {
  using V = Vec<Dim>;

  /// The step's loading: load factor and prescribed-displacement fraction at its end, the
  /// fraction reached before it, its length, and whether inertia (Newmark) and a ramped gravity
  /// take part.
  struct Loading {
    double lambda_end = 1, ramp_end = 1, ramp_committed = 0, dt = 1;
    bool dynamic = false, gravity_ramped = true;
  };

  ParticleGridMap<Dim, Shape> map;
  std::vector<double> node_mass; ///< per active node (the map's node numbers)
  /// Per node: the prescribed box that holds it (-1 if none), and per component the face that
  /// receives its reaction (FaceConditions::reaction_faces).
  std::vector<std::int32_t> node_region;
  std::vector<std::array<std::int8_t, Dim>> reaction_face;
  std::vector<Index> node_dof;       ///< per (node, component) at Dim n + a: DOF, -1 for none
  std::vector<double> prescribed_du; ///< per (node, component): this step's increment
  Index dof_count = 0;
  Eigen::VectorXd external;          ///< per unknown: the load
  std::vector<double> full_external; ///< per (node, component): the load (reactions)
  double force_scale = 1;
  std::vector<double> dof_mass, grid_v, grid_a; ///< Newmark state per unknown (dynamic)
  GhostPenalty<Dim> ghost;

  Index dof_of(Index node, int a) const { return node_dof[at(Dim * node + a)]; }

  /// Sets everything up for the scene's points where they stand; young[m] is material m's
  /// Young's modulus (the ghost penalty's scale).
  void prepare(Scene<Dim>& scene, const Loading& l, const std::vector<double>& young) {
    const auto& P = scene.particles;
    map.update(scene.grid, P);
    const auto nn = at(map.node_count());
    node_mass.assign(nn, 0.0);
    double heaviest = 0;
    for (Index n = 0; n < map.node_count(); ++n) {
      double m = 0;
      map.for_each_particle_of(n, [&](Index p, double w, const V&) { m += w * P.mass[at(p)]; });
      node_mass[at(n)] = m;
      heaviest = std::max(heaviest, m);
    }
    if (!scene.spec.prescribed.empty())
      place_prescribed_boxes<Dim>(scene, l.ramp_committed);
    node_region.resize(nn);
    reaction_face.resize(nn);
    for (Index n = 0; n < map.node_count(); ++n) {
      node_region[at(n)] = scene.prescribed_boxes.region_of(map.nodes().position(n));
      reaction_face[at(n)] = scene.face_conditions.reaction_faces(map.nodes().ijk(n));
    }
    number_unknowns(scene, l, heaviest);
    prepare_ghost_penalty(scene, heaviest, young);
    if (l.dynamic)
      project_inertia(P);
    gather_loads(scene, l);
  }

private:
  static std::size_t at(Index i) { return static_cast<std::size_t>(i); }

  // One unknown per component of a node with mass that neither a face nor a prescribed box
  // holds; a prescribed component takes this step's share of its displacement.
  void number_unknowns(const Scene<Dim>& scene, const Loading& l, double heaviest) {
    const auto nn = at(map.node_count());
    node_dof.assign(Dim * nn, -1);
    prescribed_du.assign(Dim * nn, 0.0);
    dof_count = 0;
    for (Index n = 0; n < map.node_count(); ++n) {
      const std::int32_t region = node_region[at(n)];
      const std::uint8_t mask = scene.face_conditions.held(map.nodes().ijk(n));
      for (int a = 0; a < Dim; ++a) {
        // A prescribed component wins over a face condition on the same node.
        if (region >= 0) {
          const auto& value = scene.spec.prescribed[at(region)].displacement[at(a)];
          if (value) {
            prescribed_du[at(Dim * n + a)] = (l.ramp_end - l.ramp_committed) * *value;
            continue;
          }
        }
        if (node_mass[at(n)] < kImplicitTinyNodeMassFraction * heaviest || (mask & (1u << a)))
          continue;
        node_dof[at(Dim * n + a)] = dof_count++;
      }
    }
  }

  // The faces the ghost penalty stabilises at this step's configuration.
  void prepare_ghost_penalty(const Scene<Dim>& scene, double heaviest,
                             const std::vector<double>& young) {
    const double gamma = scene.spec.solver.ghost_penalty;
    if (gamma <= 0.0)
      return;
    const auto nn = at(map.node_count());
    node_active_.assign(nn, 0);
    node_modulus_.assign(nn, 0.0);
    for (Index n = 0; n < map.node_count(); ++n) {
      node_active_[at(n)] = node_mass[at(n)] >= kImplicitTinyNodeMassFraction * heaviest;
      map.for_each_particle_of(n, [&](Index p, double, const V&) {
        const double E = young[at(scene.particles.material[at(p)])];
        node_modulus_[at(n)] = std::max(node_modulus_[at(n)], E);
      });
    }
    std::array<bool, 2 * Dim> mirror_faces{};
    for (int f = 0; f < 2 * Dim; ++f)
      mirror_faces[at(f)] = scene.spec.boundaries[f] == FaceCondition::Roller;
    if constexpr (Axisymmetric) // the axis is a symmetry line whatever x_min's condition
      mirror_faces[0] = mirror_faces[0] || scene.grid.origin()[0] == 0.0;
    ghost.build(map.nodes(), node_active_, node_modulus_, gamma, mirror_faces);
    if constexpr (Axisymmetric)
      ghost.weight_by_radius(map.nodes());
  }

  // Lumped mass and the mass-weighted projections of the particles' velocity and acceleration,
  // per unknown.
  void project_inertia(const Particles<Dim>& P) {
    dof_mass.assign(at(dof_count), 0.0);
    grid_v.assign(at(dof_count), 0.0);
    grid_a.assign(at(dof_count), 0.0);
    for (Index n = 0; n < map.node_count(); ++n) {
      V mv = V::Zero(), ma = V::Zero();
      map.for_each_particle_of(n, [&](Index p, double w, const V&) {
        mv += w * P.mass[at(p)] * P.v[at(p)];
        ma += w * P.mass[at(p)] * P.acceleration[at(p)];
      });
      for (int a = 0; a < Dim; ++a) {
        const Index dof = dof_of(n, a);
        if (dof < 0)
          continue;
        dof_mass[at(dof)] = node_mass[at(n)];
        grid_v[at(dof)] = mv[a] / node_mass[at(n)];
        grid_a[at(dof)] = ma[a] / node_mass[at(n)];
      }
    }
  }

  // Point loads, gravity and tractions at the step's end, and the force scale: the largest
  // load on a point, or with inertia m (|v| / dt + |a|), or without any load the force of a
  // cell strained by 1e-6.
  void gather_loads(const Scene<Dim>& scene, const Loading& l) {
    const auto& P = scene.particles;
    external.setZero(static_cast<Eigen::Index>(dof_count));
    full_external.assign(Dim * at(map.node_count()), 0.0);
    const V g = head<Dim>(scene.spec.gravity);
    force_scale = 0;
    for (Index p = 0; p < P.size(); ++p) {
      const V f = l.lambda_end * P.external_force[at(p)] +
                  (l.gravity_ramped ? l.lambda_end : 1.0) * P.mass[at(p)] * g;
      force_scale = std::max(force_scale, f.template lpNorm<Eigen::Infinity>());
      map.for_each_node_of(p, [&](Index n, double w, const V&) { add_external(n, w * f); });
    }
    for (const SurfaceLoad<Dim>& load : scene.surface_loads) {
      const V f = (load.constant ? 1.0 : l.lambda_end) * load.force;
      force_scale = std::max(force_scale, f.template lpNorm<Eigen::Infinity>());
      for_each_surface_load_node<Dim>(map.nodes(), P, load, map.stencil(load.particle).start,
                                      Shape::kWidth,
                                      [&](Index n, double w) { add_external(n, w * f); });
    }
    if (l.dynamic)
      for (Index p = 0; p < P.size(); ++p)
        force_scale = std::max(
            force_scale, P.mass[at(p)] * (P.v[at(p)].norm() / l.dt + P.acceleration[at(p)].norm()));
    if (force_scale == 0) {
      double modulus = 0;
      for (const auto& m : scene.materials)
        modulus = std::max(modulus, m->lame().p_wave_modulus());
      force_scale = 1e-6 * modulus * scene.grid.cell_size();
    }
  }

  void add_external(Index n, const V& f) {
    for (int a = 0; a < Dim; ++a) {
      full_external[at(Dim * n + a)] += f[a];
      if (const Index dof = dof_of(n, a); dof >= 0)
        external[dof] += f[a];
    }
  }

  std::vector<char> node_active_;    ///< per node: carries mass this step (ghost penalty)
  std::vector<double> node_modulus_; ///< per node: stiffest material it sees (ghost penalty)
};

} // namespace talus
