#pragma once
// What an implicit load step is posed on, set up once at its start (updated Lagrangian): the
// connectivity at the step's start configuration, the node masses, the unknowns (one per
// component of a node with mass that no face holds), the prescribed increments, the loads with
// the force scale Newton's tolerance is relative to, the ghost-penalty faces, and for Newmark
// the lumped mass with the projected velocity and acceleration per unknown
// (implicit_solver_impl.hpp assembles and solves on it). Each rank sets up its own points' step (a
// serial run is a run on one rank): the halo (parallel/node_halo.hpp) makes the node sums
// whole, every unknown gets its global id, and the ghost-penalty faces come from a view of the
// neighbours' nodes.
#include "talus/grid/particle_grid_map.hpp"
#include "talus/linalg/node_layout.hpp"
#include "talus/parallel/node_halo.hpp"
#include "talus/scene/scene.hpp"
#include "talus/solver/ghost_penalty.hpp"

#include "consolidation.hpp"
#include "consolidation_setup.hpp"
#include "implicit_node_fields.hpp"
#include "pressure_projection.hpp"
#include "shared_unknowns.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <cstdint>
#include <iterator>
#include <limits>
#include <optional>
#include <string>
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
  ImplicitNodeFields<Dim> node; ///< per active node (the map's node numbers)
  /// The nodes this rank shares with the others (none on one rank).
  NodeHalo<Dim> halo;
  /// Per (node, field, component): the unknown, or none. The unknowns of the nodes this rank
  /// owns come first (owned_dof_count of them), then those of the nodes it shares with a lower
  /// rank; each node's components are consecutive.
  NodeDofs dofs{NodeLayout(Dim)};
  Index owned_dof_count = 0;
  std::vector<Index> dof_gid;  ///< per unknown: its global id
  Index global_dof_count = 0;  ///< the unknowns of every rank (owned ones counted once)
  Index global_node_count = 0; ///< the active nodes of every rank (each counted once)
  Index dof_count = 0;
  /// The unknowns a platen's nodes share (shared_unknowns.hpp); Newton solves for the reduced.
  SharedUnknowns shared;
  /// Whether this step's sharing differs from the last step's (the reduced pattern then does).
  bool sharing_changed = false;
  Eigen::VectorXd external; ///< per unknown: the load
  double force_scale = 1;
  std::vector<double> dof_mass, grid_v, grid_a; ///< Newmark state per unknown (dynamic)
  GhostPenalty<Dim> ghost;

  /// Consolidation (consolidation.hpp): its model, and the pore pressure's field in the
  /// layout; none and -1 without.
  std::optional<Consolidation<Dim>> consolidation;
  int pressure_field = -1;
  PressureProjection<Dim> projection; ///< consolidation's stabilisation, by cell

  /// The unknown of displacement component a of a node, or a negative value.
  Index displacement_dof(Index node, int a) const {
    return dofs.dof(node, NodeLayout::kDisplacement, a);
  }
  /// The unknown of a node's pore pressure, or a negative value (also without consolidation).
  Index pressure_dof(Index node) const {
    return pressure_field < 0 ? NodeDofs::kNone : dofs.dof(node, pressure_field, 0);
  }

  /// The layout of the case's unknowns: the displacement, and the pore pressure in a
  /// consolidation case. Call once, before the first step.
  void lay_out(const Scene<Dim>& scene) {
    consolidation = Consolidation<Dim>::of(scene.spec, scene.grid.cell_size());
    NodeLayout layout(Dim);
    if (consolidation)
      pressure_field = layout.add_field("pore_pressure", 1);
    dofs = NodeDofs(std::move(layout));
  }

  /// Sets everything up for the scene's points where they stand; young[m] is material m's
  /// Young's modulus (the ghost penalty's scale). Collective.
  void prepare(Scene<Dim>& scene, const Loading& l, const std::vector<double>& young) {
    const auto& P = scene.particles;
    update_map(scene);
    const double heaviest = scene.decomposition->comm().max(sum_node_masses(scene));
    if (!scene.spec.prescribed.empty())
      place_prescribed_boxes<Dim>(scene, l.ramp_committed);
    prepare_ghost_penalty(scene, heaviest, young); // may add nodes
    node.resize(map.node_count(), consolidation.has_value());
    for (Index n = 0; n < map.node_count(); ++n) {
      node.region[at(n)] = scene.prescribed_boxes.region_of(map.nodes().position(n));
      node.reaction_face[at(n)] = scene.face_conditions.reaction_faces(map.nodes().ijk(n));
      node.owner[at(n)] = halo.owner(n);
    }
    if (consolidation) {
      consolidation->flow_time = scene.water.undrained() ? 0.0 : l.dt;
      consolidation->set_pressure_unit(consolidation->flow_time, scene.grid.cell_size());
      consolidation->set_gravity_share(l.gravity_ramped ? l.lambda_end : 1.0);
      prepare_pore_pressure(scene);
    }
    number_unknowns(scene, l, heaviest);
    if (l.dynamic)
      project_inertia(P);
    gather_loads(scene, l);
  }

  /// This rank (the owner of the nodes it owns).
  int rank() const { return rank_; }

private:
  // One unknown per component of a node with mass that neither a face nor a prescribed box
  // holds; a prescribed component takes this step's share of its displacement. The owned
  // nodes are numbered first; then every unknown learns its global id.
  void number_unknowns(const Scene<Dim>& scene, const Loading& l, double heaviest) {
    const auto nn = at(map.node_count());
    dofs.reset(map.node_count());
    node.prescribed_du.assign(nn, V::Zero());
    dof_count = 0;
    for (const bool owned : {true, false})
      for (Index n = 0; n < map.node_count(); ++n) {
        if ((node.owner[at(n)] == rank_) != owned)
          continue;
        const std::int32_t region = node.region[at(n)];
        const std::uint8_t mask = scene.face_conditions.held(map.nodes().ijk(n));
        for (int a = 0; a < Dim; ++a) {
          // A prescribed component wins over a face condition on the same node.
          if (region >= 0) {
            const auto& value = scene.spec.prescribed[at(region)].displacement[at(a)];
            if (value) {
              node.prescribed_du[at(n)][a] = (l.ramp_end - l.ramp_committed) * *value;
              continue;
            }
          }
          if (node.mass[at(n)] < kImplicitTinyNodeMassFraction * heaviest || (mask & (1u << a)))
            continue;
          dofs.set(n, NodeLayout::kDisplacement, a, dof_count++);
        }
        if (consolidation && !node.drained[at(n)] &&
            node.mass[at(n)] >= kImplicitTinyNodeMassFraction * heaviest)
          dofs.set(n, pressure_field, 0, dof_count++);
        if (owned)
          owned_dof_count = dof_count;
      }
    owned_dof_count = std::min(owned_dof_count, dof_count);
    number_globally(scene.decomposition->comm());
    share_platens(scene);
  }

  // A platen's nodes share its normal displacement: one group per platen face.
  void share_platens(const Scene<Dim>& scene) {
    shared.reset(owned_dof_count);
    for (Index n = 0; n < map.node_count() && scene.face_conditions.has_platen(); ++n)
      for (int a = 0; a < Dim; ++a)
        if (const Index dof = displacement_dof(n, a); dof >= 0)
          if (const int face = scene.face_conditions.platen(map.nodes().ijk(n), a); face >= 0) {
            if (dof >= owned_dof_count) // a run refuses a platen over several ranks at start
              throw std::logic_error("a platen's unknown on a node another rank owns");
            shared.share(dof, face);
          }
    sharing_changed = shared.finish();
  }

  // The nodes' pore pressure at the step's start: the points' projected, and on the drained
  // nodes the water table's then, with its increment to the step's end (scene.water). The
  // table's, not the projection: the points next to a drained face take only the table's
  // change from it, not the difference between it and their own mean.
  void prepare_pore_pressure(const Scene<Dim>& scene) {
    project_node_pressure(map, scene.particles, halo, node.mass, node.pressure);
    mark_drained_nodes(map, scene.particles, halo, scene.spec.water->drained, node.drained);
    projection.prepare(scene.grid, scene.particles, consolidation->projection());
    for (Index n = 0; n < map.node_count(); ++n) {
      node.prescribed_dp[at(n)] = 0.0;
      if (!node.drained[at(n)])
        continue;
      const V x = map.nodes().position(n);
      node.pressure[at(n)] = scene.water.template pore_pressure_at_start<Dim>(x);
      node.prescribed_dp[at(n)] = scene.water.template pore_pressure<Dim>(x) - node.pressure[at(n)];
    }
  }

  // Global ids: each rank's owned unknowns in order after those of the lower ranks; a shared
  // node's ids reach the other ranks holding it by the halo sum (its owner adds id + 1, the
  // others 0).
  void number_globally(const Communicator& comm) {
    const auto counts = comm.all_gather(owned_dof_count);
    Index offset = 0;
    global_dof_count = 0;
    for (int r = 0; r < comm.size(); ++r) {
      if (r < comm.rank())
        offset += counts[at(r)];
      global_dof_count += counts[at(r)];
    }
    Index owned_nodes = 0;
    for (Index n = 0; n < map.node_count(); ++n)
      owned_nodes += node.owner[at(n)] == rank_;
    global_node_count = comm.sum(std::int64_t{owned_nodes});
    const std::span<const Index> table = dofs.table();
    std::vector<double> id_plus_one(table.size(), 0.0);
    for (std::size_t k = 0; k < table.size(); ++k)
      if (const Index dof = table[k]; dof >= 0 && dof < owned_dof_count)
        id_plus_one[k] = static_cast<double>(offset + dof + 1);
    const typename NodeHalo<Dim>::Field field{id_plus_one.data(), dofs.layout().width()};
    halo.sum({&field, 1});
    dof_gid.assign(at(dof_count), -1);
    for (std::size_t k = 0; k < table.size(); ++k)
      if (const Index dof = table[k]; dof >= 0)
        dof_gid[at(dof)] = static_cast<Index>(id_plus_one[k]) - 1;
    if (std::any_of(dof_gid.begin(), dof_gid.end(), [](Index g) { return g < 0; }))
      throw std::logic_error("a shared node's unknown has no global id from its owner");
  }

  // The map of the step's points; a point that left the grid on any rank stops every rank
  // with its message, and the halo connects the nodes the ranks share.
  void update_map(const Scene<Dim>& scene) {
    std::optional<std::string> failure;
    try {
      map.update(scene.grid, scene.particles);
    } catch (const NumericalError& e) {
      failure = e.what();
    }
    const Communicator& comm = scene.decomposition->comm();
    if (const auto first = comm.first_message(failure))
      throw NumericalError(*first);
    rank_ = comm.rank();
    halo.connect(*scene.decomposition, map.nodes());
  }

  // The nodes' masses (summed over the ranks that share a node); returns the heaviest here.
  double sum_node_masses(const Scene<Dim>& scene) {
    const auto& P = scene.particles;
    node.mass.assign(at(map.node_count()), 0.0);
    double heaviest = 0;
    for (Index n = 0; n < map.node_count(); ++n) {
      double m = 0;
      map.for_each_particle_of(n, [&](Index p, double w, const V&) { m += w * P.mass[at(p)]; });
      node.mass[at(n)] = m;
    }
    const typename NodeHalo<Dim>::Field field{node.mass.data(), 1};
    halo.sum({&field, 1});
    for (const double m : node.mass)
      heaviest = std::max(heaviest, m);
    return heaviest;
  }

  // The faces the ghost penalty stabilises at this step's configuration. Whether a face is
  // stabilised depends on the nodes up to two cells around it, which may belong to other ranks.
  // The faces are found on a view of the grid, this rank's nodes and the neighbours' within
  // its reach; each face is assembled by the owner of its anchor node, which adds the face's
  // nodes that no point of its own reaches to its nodes (they carry no mass of its own; the
  // halo brings their mass and unknowns' ids).
  void prepare_ghost_penalty(const Scene<Dim>& scene, double heaviest,
                             const std::vector<double>& young) {
    const double gamma = scene.spec.solver.ghost_penalty;
    if (gamma <= 0.0)
      return;
    node_moduli(scene, young);
    const auto nn = at(map.node_count());
    std::vector<double> mine(2 * nn);
    for (std::size_t n = 0; n < nn; ++n) {
      mine[2 * n] = node.mass[n];
      mine[2 * n + 1] = node_modulus_[n];
    }
    const auto theirs = halo.neighbour_nodes(map.nodes(), mine, 2);
    // The view: every node this rank holds or a neighbour sent, with its (whole) mass, the
    // stiffest modulus any holder saw, and its lowest holder (id lists merged, both ascending).
    std::vector<Index> own(nn), sent = theirs.lattice_id, ids;
    for (Index n = 0; n < map.node_count(); ++n)
      own[at(n)] = map.nodes().lattice_id(n);
    std::sort(sent.begin(), sent.end());
    ids.reserve(own.size() + sent.size());
    std::merge(own.begin(), own.end(), sent.begin(), sent.end(), std::back_inserter(ids));
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    ActiveNodes<Dim> view;
    view.assign(scene.grid, ids);
    std::vector<Index> node_of_view = nodes_of_view(view);
    std::vector<double> mass(ids.size(), 0.0), modulus(ids.size(), 0.0);
    std::vector<int> lowest(ids.size(), std::numeric_limits<int>::max());
    for (std::size_t v = 0; v < ids.size(); ++v) {
      const Index n = node_of_view[v];
      if (n < 0)
        continue;
      mass[v] = node.mass[at(n)];
      modulus[v] = node_modulus_[at(n)];
      lowest[v] = halo.owner(n);
    }
    for (std::size_t i = 0; i < theirs.rank.size(); ++i) {
      const auto v = at(view.find_lattice_id(theirs.lattice_id[i]));
      if (node_of_view[v] < 0) {
        mass[v] = theirs.values[2 * i];
        lowest[v] = std::min(lowest[v], theirs.rank[i]);
      }
      modulus[v] = std::max(modulus[v], theirs.values[2 * i + 1]);
    }
    std::vector<char> active(ids.size());
    for (std::size_t v = 0; v < ids.size(); ++v)
      active[v] = mass[v] >= kImplicitTinyNodeMassFraction * heaviest;
    ghost.build(view, active, modulus, gamma, mirror_faces(scene));
    using Ghost = GhostPenalty<Dim>;
    const auto mine_to_assemble = [&](const typename Ghost::Face& f) {
      return lowest[at(Ghost::anchor(f))] == rank_;
    };
    std::vector<Index> extra;
    for (const auto& face : ghost.faces())
      if (mine_to_assemble(face))
        for (const Index v : face.nodes)
          if (node_of_view[at(v)] < 0)
            extra.push_back(view.lattice_id(v));
    std::sort(extra.begin(), extra.end());
    extra.erase(std::unique(extra.begin(), extra.end()), extra.end());
    // Every rank reconnects (collective), whether it added nodes or not.
    const bool added = scene.decomposition->comm().any(!extra.empty());
    if (added) {
      if (!extra.empty())
        map.add_nodes(std::move(extra));
      halo.connect(*scene.decomposition, map.nodes());
      sum_node_masses(scene);
      node_of_view = nodes_of_view(view);
    }
    ghost.select(mine_to_assemble, [&](Index v) { return node_of_view[at(v)]; });
    if constexpr (Axisymmetric)
      ghost.weight_by_radius(map.nodes());
  }

  // Per node of the view (whose ids include all of the map's): the map's node, or -1.
  std::vector<Index> nodes_of_view(const ActiveNodes<Dim>& view) const {
    std::vector<Index> node(at(view.size()), -1);
    Index n = 0;
    for (Index v = 0; v < view.size() && n < map.node_count(); ++v)
      if (view.lattice_id(v) == map.nodes().lattice_id(n))
        node[at(v)] = n++;
    return node;
  }

  // node_modulus_: per node, the stiffest material among the points that reach it here.
  void node_moduli(const Scene<Dim>& scene, const std::vector<double>& young) {
    node_modulus_.assign(at(map.node_count()), 0.0);
    for (Index n = 0; n < map.node_count(); ++n)
      map.for_each_particle_of(n, [&](Index p, double, const V&) {
        const double E = young[at(scene.particles.material[at(p)])];
        node_modulus_[at(n)] = std::max(node_modulus_[at(n)], E);
      });
  }

  // The grid faces that are symmetry planes for the ghost penalty's band test.
  static std::array<bool, 2 * Dim> mirror_faces(const Scene<Dim>& scene) {
    std::array<bool, 2 * Dim> mirror{};
    for (int f = 0; f < 2 * Dim; ++f)
      mirror[at(f)] = scene.spec.boundaries[f] == FaceCondition::Roller;
    if constexpr (Axisymmetric) // the axis is a symmetry line whatever x_min's condition
      mirror[0] = mirror[0] || scene.grid.origin()[0] == 0.0;
    return mirror;
  }

  // Lumped mass and the mass-weighted projections of the particles' velocity and acceleration,
  // per unknown.
  void project_inertia(const Particles<Dim>& P) {
    const auto nn = at(map.node_count());
    std::vector<V> mv(nn, V::Zero()), ma(nn, V::Zero()); // per node: m v and m a
    for (Index n = 0; n < map.node_count(); ++n)
      map.for_each_particle_of(n, [&](Index p, double w, const V&) {
        mv[at(n)] += w * P.mass[at(p)] * P.v[at(p)];
        ma[at(n)] += w * P.mass[at(p)] * P.acceleration[at(p)];
      });
    const typename NodeHalo<Dim>::Field fields[] = {NodeHalo<Dim>::field(mv),
                                                    NodeHalo<Dim>::field(ma)};
    halo.sum(fields);
    dof_mass.assign(at(dof_count), 0.0);
    grid_v.assign(at(dof_count), 0.0);
    grid_a.assign(at(dof_count), 0.0);
    for (Index n = 0; n < map.node_count(); ++n)
      for (int a = 0; a < Dim; ++a) {
        const Index dof = displacement_dof(n, a);
        if (dof < 0)
          continue;
        dof_mass[at(dof)] = node.mass[at(n)];
        grid_v[at(dof)] = mv[at(n)][a] / node.mass[at(n)];
        grid_a[at(dof)] = ma[at(n)][a] / node.mass[at(n)];
      }
  }

  // Point loads, gravity and tractions at the step's end (summed over the ranks sharing a
  // node), and the force scale: the largest load on a point, or with inertia m (|v| / dt +
  // |a|), or without any load the force of a cell strained by 1e-6.
  void gather_loads(const Scene<Dim>& scene, const Loading& l) {
    const auto& P = scene.particles;
    node.load.assign(at(map.node_count()), V::Zero());
    const V g = head<Dim>(scene.spec.gravity);
    force_scale = 0;
    auto add = [&](Index n, const V& f) { node.load[at(n)] += f; };
    for (Index p = 0; p < P.size(); ++p) {
      const V f = l.lambda_end * P.external_force[at(p)] +
                  (l.gravity_ramped ? l.lambda_end : 1.0) * P.mass[at(p)] * g;
      force_scale = std::max(force_scale, f.template lpNorm<Eigen::Infinity>());
      map.for_each_node_of(p, [&](Index n, double w, const V&) { add(n, w * f); });
    }
    for (const SurfaceLoad<Dim>& load : scene.surface_loads) {
      const V f = (load.constant ? 1.0 : l.lambda_end) * load.force;
      force_scale = std::max(force_scale, f.template lpNorm<Eigen::Infinity>());
      for_each_surface_load_node<Dim>(map.nodes(), P, load, map.stencil(load.particle).start,
                                      Shape::kWidth, [&](Index n, double w) { add(n, w * f); });
    }
    if (l.dynamic)
      for (Index p = 0; p < P.size(); ++p)
        force_scale = std::max(
            force_scale, P.mass[at(p)] * (P.v[at(p)].norm() / l.dt + P.acceleration[at(p)].norm()));
    const typename NodeHalo<Dim>::Field field = NodeHalo<Dim>::field(node.load);
    halo.sum({&field, 1});
    force_scale = scene.decomposition->comm().max(force_scale);
    external.setZero(static_cast<Eigen::Index>(dof_count));
    for (Index n = 0; n < map.node_count(); ++n)
      for (int a = 0; a < Dim; ++a)
        if (const Index dof = displacement_dof(n, a); dof >= 0)
          external[dof] += node.load[at(n)][a];
    // A load below the stress's round-off (eps E h) is no load: a scale that small made the
    // tolerance infinite and KINSOL's line search loop on overflowed norms.
    double modulus = 0;
    for (const auto& m : scene.materials)
      modulus = std::max(modulus, m->lame().p_wave_modulus());
    const double cell_force = modulus * scene.grid.cell_size();
    if (force_scale <= 1e3 * std::numeric_limits<double>::epsilon() * cell_force)
      force_scale = 1e-6 * cell_force;
  }

  std::vector<double> node_modulus_; ///< per node: stiffest material it sees (ghost penalty)
  int rank_ = 0;
};

} // namespace talus
