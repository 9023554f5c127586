#include "talus/solver/explicit_solver.hpp"
#include "talus/scene/pore_water.hpp"

#include "talus/core/parallel.hpp"
#include "talus/grid/grid_state.hpp"
#include "talus/grid/particle_grid_map.hpp"
#include "talus/parallel/node_halo.hpp"
#include "talus/shape/shape_functions.hpp"
#include "talus/solver/rank_sums.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <span>

namespace talus {

namespace {

// Axisymmetric (Dim 2 only): x = r, y = z, volumes and masses per radian. The hoop stretch
// moves with the radial velocity, L33 = sum_i N_i v_i,r / r, and the hoop stress pulls the
// radial force, f_i,r -= V sigma33 N_i / r, both at the radius r_n where the weights are taken.
template <int Dim, class Shape, bool Axisymmetric>
class ExplicitSolverImpl final : public ExplicitSolver {
  static_assert(Dim == 2 || !Axisymmetric, "axisymmetry is a 2D geometry");
  using V = Vec<Dim>;
  using M = Mat<Dim>;

public:
  ExplicitSolverImpl(Scene<Dim>& scene, bool stress_current) : scene_(scene) {
    const auto& P = scene.particles;
    for (auto& r : reactions_)
      r.setZero();
    apic_ = scene.spec.solver.transfer == TransferScheme::Apic;
    // The scene starts C_p from the initial velocity field; a later stage keeps what the
    // previous one left.
    if (apic_ && scene.particles.affine_velocity.size() != static_cast<std::size_t>(P.size()))
      throw std::logic_error("APIC transfer without the points' affine velocities");
    for (const auto& material : scene.materials)
      wave_speed_.push_back(material->wave_speed());
    // Stress consistent with the initial F: a plastic model's evaluation at an unchanged F
    // may still move its stress by round-off, so a resumed stage, whose stress is current,
    // does not repeat it.
    if (!stress_current)
      update_stress();
  }

  void step(double dt) override {
    update_map();
    size_node_arrays();
    halo_.connect(*scene_.decomposition, map_.nodes());
    if constexpr (Axisymmetric) {
      const auto& P = scene_.particles;
      radius_n_.resize(at(P.size()));
      for (std::size_t s = 0; s < radius_n_.size(); ++s)
        radius_n_[s] = P.x[s][0];
    }
    switch (scene_.spec.solver.scheme) {
    case UpdateScheme::USF:
      gather<kMass>();
      grid_velocity_from_momentum();
      update_kinematics_and_stress(dt);
      gather<kForce>();
      grid_acceleration(dt);
      particle_update(dt);
      break;
    case UpdateScheme::USL:
      gather<kMass | kForce>();
      grid_velocity_from_momentum();
      grid_acceleration(dt);
      particle_update(dt);
      update_kinematics_and_stress(dt);
      break;
    case UpdateScheme::MUSL:
      gather<kMass | kForce>();
      grid_velocity_from_momentum();
      grid_acceleration(dt);
      particle_update(dt);
      remap_velocity(); // velocity gradient from the updated particle velocities
      update_kinematics_and_stress(dt);
      break;
    }
  }

  // A point that left the grid stops every rank, before any of them waits for the others' sums.
  void update_map() {
    std::optional<std::string> failure;
    try {
      map_.update(scene_.grid, scene_.particles);
    } catch (const NumericalError& e) {
      failure = e.what();
    }
    if (const auto first = ranks().first_message(failure))
      throw NumericalError(*first);
  }

  double stable_dt(double cfl) const override {
    const auto& P = scene_.particles;
    const double max_speed = parallel_reduce(
        P.size(), 0.0,
        [&](double& fastest, Index begin, Index end) {
          for (auto s = at(begin); s < at(end); ++s)
            fastest = std::max(fastest, wave_speed_[at(P.material[s])] + P.v[s].norm());
        },
        [](double& fastest, double block) { fastest = std::max(fastest, block); });
    return cfl * scene_.grid.cell_size() / ranks().max(max_speed);
  }

  Energies energies() const override {
    const Energies e = particle_energies(scene_, true);
    return summed_over_ranks(e, ranks());
  }

  FaceReactions reactions() const override { return summed_over_ranks(reactions_, ranks()); }
  Index active_nodes() const override { return map_.node_count(); }

  std::optional<StateViolation> grid_violation() const override {
    if (auto v = find_node_violation<Dim>(map_.nodes(), state_.velocity, "grid velocity"))
      return v;
    return find_node_violation<Dim>(map_.nodes(), state_.acceleration, "grid acceleration");
  }

  // The map and the grid arrays are rebuilt every step: nothing is kept per point.
  void particles_changed() override {}

private:
  const Communicator& ranks() const { return scene_.decomposition->comm(); }
  Index node_count() const { return map_.node_count(); }
  V node_position(Index n) const { return map_.nodes().position(n); }

  // The step's node arrays, one entry per active node, and the faces' conditions on them.
  void size_node_arrays() {
    state_.resize(node_count());
    parallel_for(node_count(), [&](Index n) {
      const auto ijk = map_.nodes().ijk(n);
      state_.held[at(n)] = scene_.face_conditions.held(ijk);
      state_.reaction_face[at(n)] = scene_.face_conditions.reaction_faces(ijk);
    });
    // The nodes that report a reaction, in ascending order: the reactions' sums run over them
    // alone and in a fixed order.
    reaction_nodes_.clear();
    for (Index n = 0; n < node_count(); ++n)
      if (std::any_of(state_.reaction_face[at(n)].begin(), state_.reaction_face[at(n)].end(),
                      [](std::int8_t face) { return face >= 0; }))
        reaction_nodes_.push_back(n);
  }

  // What one P2G gather collects: mass and momentum, and/or the nodal force.
  static constexpr int kMass = 1;
  static constexpr int kForce = 2;

  // What a gather reads of each point, per slot (ParticleGridMap: the points bin by bin), built
  // in one parallel pass: the gathers then sweep these arrays in order, and each visit of a
  // point from one of its W^Dim nodes costs a few multiply-adds. APIC's momentum at node x_i,
  // m (v + C (x_i - x_a)) with x_a the point's position at the start of the step, is kept as
  // m (v - C x_a) and m C, whose weighted sum is multiplied by x_i once per node.
  struct MassLoad {
    double m;
    V mv;
  };
  struct ForceLoad {
    M stress_volume; ///< -V sigma on the grid's axes: the force is stress_volume grad(N)
    V body;          ///< point load plus gravity, m g
    double hoop;     ///< axisymmetry: V sigma_33 / r, pulling the radial force
  };

  // Fills the mass loads (momentum anchored at `anchor`, APIC) and/or the force loads.
  template <int kWhat> void fill_loads(const std::vector<V>& anchor) {
    const auto& P = scene_.particles;
    const auto np = at(P.size());
    if constexpr ((kWhat & kMass) != 0) {
      mass_load_.resize(np);
      if (apic_)
        affine_momentum_.resize(np);
    }
    if constexpr ((kWhat & kForce) != 0)
      force_load_.resize(np);
    const V g = head<Dim>(scene_.spec.gravity);
    const PoreWater& water = scene_.water;
    parallel_for(P.size(), [&](Index q) {
      const auto p = at(map_.point_at_slot(q));
      const auto s = at(q);
      if constexpr ((kWhat & kMass) != 0) {
        if (apic_) {
          const M mC = P.mass[p] * P.affine_velocity[p];
          mass_load_[s] = {P.mass[p], P.mass[p] * P.v[p] - mC * anchor[p]};
          affine_momentum_[s] = mC;
        } else {
          mass_load_[s] = {P.mass[p], P.mass[p] * P.v[p]};
        }
      }
      if constexpr ((kWhat & kForce) != 0) {
        ForceLoad& l = force_load_[s];
        l.stress_volume = -P.volume[p] * P.stress[p].template topLeftCorner<Dim, Dim>();
        l.body = P.external_force[p] + P.mass[p] * g;
        if constexpr (Axisymmetric)
          l.hoop = P.volume[p] * P.stress[p](2, 2) / radius_n_[p];
        if (water.any()) // effective stress, and -grad u over the volume (pore_water.hpp)
          add_water(p, l);
      }
    });
  }

  // P2G as a gather over the nodes (each node sums its points in the map's fixed order, so the
  // result does not depend on the thread count). Mass, momentum and force share one pass where
  // the scheme allows (USL, MUSL): one visit, and one weight and gradient, per point and node.
  // Tractions are added after the gather.
  template <int kWhat> void gather() {
    fill_loads<kWhat>(scene_.particles.x);
    parallel_for(node_count(), [&](Index n) {
      double m = 0;
      V mv = V::Zero(), f = V::Zero();
      M mC = M::Zero();
      auto add = [&](Index q, double w, [[maybe_unused]] const V& grad) {
        const auto s = at(q);
        if constexpr ((kWhat & kMass) != 0) {
          m += w * mass_load_[s].m;
          mv += w * mass_load_[s].mv;
          if (apic_)
            mC += w * affine_momentum_[s];
        }
        if constexpr ((kWhat & kForce) != 0) {
          const ForceLoad& l = force_load_[s];
          f += l.stress_volume * grad + w * l.body;
          if constexpr (Axisymmetric)
            f[0] -= w * l.hoop;
        }
      };
      if constexpr ((kWhat & kForce) != 0)
        map_.for_each_slot_of(n, add);
      else
        map_.for_each_slot_weight_of(n, [&](Index q, double w) { add(q, w, V::Zero()); });
      if constexpr ((kWhat & kMass) != 0) {
        state_.mass[at(n)] = m;
        state_.momentum[at(n)] = apic_ ? V(mv + mC * node_position(n)) : mv;
      }
      if constexpr ((kWhat & kForce) != 0)
        state_.force[at(n)] = f;
    });
    if constexpr ((kWhat & kForce) != 0)
      for (const SurfaceLoad<Dim>& load : scene_.surface_loads)
        for_each_surface_load_node<Dim>(
            map_.nodes(), scene_.particles, load, map_.stencil(load.particle).start, Shape::kWidth,
            [&](Index n, double w) { state_.force[at(n)] += w * load.force; });
    std::array<typename NodeHalo<Dim>::Field, 3> fields;
    std::size_t count = 0;
    if constexpr ((kWhat & kMass) != 0) {
      fields[count++] = NodeHalo<Dim>::field(state_.mass);
      fields[count++] = NodeHalo<Dim>::field(state_.momentum);
    }
    if constexpr ((kWhat & kForce) != 0)
      fields[count++] = NodeHalo<Dim>::field(state_.force);
    halo_.sum(std::span(fields.data(), count));
  }

  void constrain(Index n, V& vec) const {
    const std::uint8_t mask = state_.held[at(n)];
    for (int d = 0; d < Dim; ++d)
      if (mask & (1u << d))
        vec[d] = 0.0;
  }

  // Only nodes that no point reaches with a non-zero weight (the edge of a GIMP support) are
  // empty. A node of tiny mass still carries the mass-weighted velocity of its points, p / m,
  // to round-off: cutting such nodes (formerly below 1e-12 of the lightest point) dropped their
  // share of the momentum and put a zero velocity into the gradients of the points that see
  // them. In 3D, where a node's weight is a product of three, that made the rigid translation's
  // stress 1e-11 E and the colliding spheres' momentum drift 1e-12 (4.5e-14 and 8e-16 now).
  void grid_velocity_from_momentum() {
    parallel_for(node_count(), [&](Index n) {
      if (state_.mass[at(n)] <= 0.0) {
        state_.velocity[at(n)].setZero();
        return;
      }
      state_.velocity[at(n)] = state_.momentum[at(n)] / state_.mass[at(n)];
      constrain(n, state_.velocity[at(n)]);
    });
  }

  // a = f / m with constraints; the reaction on a constrained component is what holds it: -f.
  void grid_acceleration(double dt) {
    for (auto& r : reactions_)
      r.setZero();
    for (const Index n : reaction_nodes_) {
      if (!halo_.counts(n))
        continue; // another rank adds this node's reaction
      for (int d = 0; d < Dim; ++d)
        if (const int face = state_.reaction_face[at(n)][static_cast<std::size_t>(d)]; face >= 0)
          reactions_[static_cast<std::size_t>(face)][d] -= state_.force[at(n)][d];
    }
    parallel_for(node_count(), [&](Index n) {
      const auto s = at(n);
      if (state_.mass[s] <= 0.0) {
        state_.acceleration[s].setZero();
        return;
      }
      state_.acceleration[s] = state_.force[s] / state_.mass[s];
      constrain(n, state_.acceleration[s]);
      state_.velocity[s] += dt * state_.acceleration[s];
    });
  }

  // FLIP/PIC blend of the particle velocity, or APIC's velocity and affine matrix; positions
  // move with the updated grid velocity.
  void particle_update(double dt) {
    auto& P = scene_.particles;
    if (apic_) {
      old_x_.resize(at(P.size()));
      parallel_for(P.size(), [&](Index q) { apic_update(q, dt); });
      return;
    }
    const double flip = scene_.spec.solver.flip;
    // The G2P loops run over the slots, which reads the stencils in order.
    parallel_for(P.size(), [&](Index q) {
      const Index p = map_.point_at_slot(q);
      V a = V::Zero(), v_new = V::Zero();
      map_.for_each_node_weight_of_slot(q, [&](Index n, double w) {
        a += w * state_.acceleration[at(n)];
        v_new += w * state_.velocity[at(n)];
      });
      const auto s = at(p);
      P.v[s] = flip * (P.v[s] + dt * a) + (1.0 - flip) * v_new;
      P.x[s] += dt * v_new;
    });
  }

  // APIC (Jiang et al. 2015): v_p = sum w v_i, C_p = B_p D_p^-1 with B_p = sum w v_i (x_i - x_p)^T
  // and D_p = sum w (x_i - x_p)(x_i - x_p)^T. For tensor-product kernels that reproduce linear
  // fields D_p is diagonal, one 1D second moment per direction. Linear hats lose that moment on
  // a node (D_dd -> 0); there the affine part in that direction is dropped. CPDI's D_p is full:
  // the mean over the corners of the hats' moment at the corner plus (x_c - x_p)(x_c - x_p)^T,
  // at least J J^T (J = F diag(lp0)), so it is regular while det F > 0.
  void apic_update(Index q, double dt) {
    auto& P = scene_.particles;
    const auto s = at(map_.point_at_slot(q));
    V v_new = V::Zero();
    M B = M::Zero();
    map_.for_each_node_weight_of_slot(q, [&](Index n, double w) {
      v_new += w * state_.velocity[at(n)];
      B += w * state_.velocity[at(n)] * (node_position(n) - P.x[s]).transpose();
    });
    const double h = scene_.grid.cell_size();
    M C = M::Zero();
    if constexpr (!tensor_product<Shape>()) {
      // CPDI: D_p = sum w (x_i - x_p)(x_i - x_p)^T is a full matrix (the sheared voxel).
      M D = M::Zero();
      map_.for_each_node_weight_of_slot(q, [&](Index n, double w) {
        const V r = node_position(n) - P.x[s];
        D += w * r * r.transpose();
      });
      C = B * D.inverse();
    } else {
      const auto& st = map_.stencil_of_slot(q);
      for (int d = 0; d < Dim; ++d) {
        double second_moment = 0;
        for (int a = 0; a < Shape::kWidth; ++a) {
          const double r =
              scene_.grid.origin()[d] + h * static_cast<double>(st.start[d] + a) - P.x[s][d];
          second_moment += st.N[d][static_cast<std::size_t>(a)] * r * r;
        }
        if (second_moment > 1e-8 * h * h)
          C.col(d) = B.col(d) / second_moment;
      }
    }
    P.v[s] = v_new;
    P.affine_velocity[s] = C;
    old_x_[s] = P.x[s];
    P.x[s] += dt * v_new;
  }

  // MUSL's second P2G, with the weights of the start of the step (the map is not rebuilt). With
  // APIC the affine field must be anchored where those weights were taken, x_p^n: anchored at
  // the moved point x_p^{n+1} = x_p^n + dt v_p it would add -dt C_p v_p to every point's
  // velocity, for a spin C_p v_p = -omega^2 (x_p - c), a spurious radial expansion
  // dt omega^2 (x - c) whose gradient dt omega^2 I entered L and F every step.
  void remap_velocity() {
    fill_loads<kMass>(old_x_);
    parallel_for(node_count(), [&](Index n) {
      V mv = V::Zero();
      M mC = M::Zero();
      map_.for_each_slot_weight_of(n, [&](Index q, double w) {
        mv += w * mass_load_[at(q)].mv;
        if (apic_)
          mC += w * affine_momentum_[at(q)];
      });
      if (apic_)
        mv += mC * node_position(n);
      state_.momentum[at(n)] = mv;
    });
    const typename NodeHalo<Dim>::Field momentum = NodeHalo<Dim>::field(state_.momentum);
    halo_.sum(std::span(&momentum, 1));
    grid_velocity_from_momentum();
  }

  // Velocity gradient from the grid, and F advanced with the increment that matches how the
  // points move. FLIP: the midpoint (Hughes-Winget) increment dF = (I - dt L/2)^-1 (I + dt L/2),
  // exactly orthogonal for a rigid spin, so a rotating body accumulates no spurious strain from
  // the time integration. APIC: each point carries its neighbourhood along its affine field,
  // x_p + r -> x_p + r + dt (v_p + C_p r), whose Jacobian is I + dt L (Jiang et al. 2015). A
  // spin then moves the points out along the tangent by (omega dt)^2 / 2 of the radius per
  // step and F records that stretch, so the material holds the disc together; with the
  // orthogonal increment F saw none of it, the disc grew 20 % and lost 40 % of its energy in
  // ten revolutions (now 0.4 %, with the angular momentum kept to 1e-3; stability_rotation).
  void update_kinematics_and_stress(double dt) {
    auto& P = scene_.particles;
    parallel_for(P.size(), [&](Index q) {
      const Index p = map_.point_at_slot(q);
      M L = M::Zero();
      [[maybe_unused]] double v_r = 0; // the radial velocity at the point (axisymmetry)
      map_.for_each_node_of_slot(q, [&](Index n, double w, const V& grad) {
        L += state_.velocity[at(n)] * grad.transpose();
        if constexpr (Axisymmetric)
          v_r += w * state_.velocity[at(n)][0];
      });
      const M half = 0.5 * dt * L;
      const M dF = apic_ ? M(M::Identity() + dt * L)
                         : M((M::Identity() - half).inverse() * (M::Identity() + half));
      const auto s = at(p);
      P.advance_F(s, dF);
      if constexpr (Axisymmetric) { // the same increment rule on the hoop rate L33
        const double L33 = v_r / radius_n_[s];
        P.F[s](2, 2) *= apic_ ? 1.0 + dt * L33 : (1.0 + 0.5 * dt * L33) / (1.0 - 0.5 * dt * L33);
      }
      P.volume[s] = P.F[s].determinant() * P.volume0[s];
    });
    update_stress();
  }

  // The materials give the effective stress; below the water table the points carry the
  // total one, sigma' - u I, with u where the point now is.
  void update_stress() {
    auto& P = scene_.particles;
    for (std::size_t m = 0; m < scene_.materials.size(); ++m)
      scene_.materials[m]->update_stress(scene_.particles_of_material[m], P.F, P.stress);
    if (scene_.water.any())
      for (std::size_t s = 0; s < P.stress.size(); ++s) {
        P.pore_pressure[s] = scene_.water.template pore_pressure<Dim>(P.x[s]);
        P.stress[s].diagonal().array() -= P.pore_pressure[s];
      }
  }

  // The grid's balance is written on the effective stress, sigma + u I, with the body force
  // -V grad u: the total stress in balance with the water's pressure on the body's faces.
  void add_water(std::size_t p, ForceLoad& l) const {
    const auto& P = scene_.particles;
    const double u = P.pore_pressure[p];
    l.stress_volume.diagonal().array() -= P.volume[p] * u;
    l.body -= P.volume[p] * scene_.water.template pressure_gradient<Dim>(P.x[p]);
    if constexpr (Axisymmetric)
      l.hoop += P.volume[p] * u / radius_n_[p];
  }

  Scene<Dim>& scene_;
  ParticleGridMap<Dim, Shape> map_;
  GridState<Dim> state_;              ///< per active node: what the step gathers and updates
  std::vector<Index> reaction_nodes_; ///< the nodes with a reaction face, ascending
  std::vector<double> wave_speed_;    ///< per material: the stable step's wave speed
  std::vector<V> old_x_; // APIC: the points' positions at the start of the step (MUSL's remap)
  std::vector<MassLoad> mass_load_;   ///< per slot: what the mass and momentum gather reads
  std::vector<M> affine_momentum_;    ///< per slot (APIC): m C
  std::vector<ForceLoad> force_load_; ///< per slot: what the force gather reads
  std::vector<double> radius_n_;      // axisymmetry: the points' radii at the start of the step
  FaceReactions reactions_{};
  bool apic_ = false;
  NodeHalo<Dim> halo_; ///< the nodes shared with other ranks (none on one rank)
};

/// ExplicitSolverImpl of one dimension, as a template of the shape function alone.
template <int Dim, bool Axisymmetric> struct ExplicitIn {
  template <class Shape> using Solver = ExplicitSolverImpl<Dim, Shape, Axisymmetric>;
};

} // namespace

template <int Dim>
std::unique_ptr<ExplicitSolver> make_explicit_solver(Scene<Dim>& scene, bool stress_current) {
  if constexpr (Dim == 2)
    if (scene.spec.geometry == Geometry::Axisymmetric)
      return make_for_shape<ExplicitSolver, ExplicitIn<2, true>::template Solver>(
          scene.spec.solver.shape, scene, stress_current);
  return make_for_shape<ExplicitSolver, ExplicitIn<Dim, false>::template Solver>(
      scene.spec.solver.shape, scene, stress_current);
}

template std::unique_ptr<ExplicitSolver> make_explicit_solver<2>(Scene<2>&, bool);
template std::unique_ptr<ExplicitSolver> make_explicit_solver<3>(Scene<3>&, bool);

} // namespace talus
