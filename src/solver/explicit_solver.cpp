#include "talus/solver/explicit_solver.hpp"

#include "talus/core/parallel.hpp"
#include "talus/grid/particle_grid_map.hpp"
#include "talus/shape/shape_functions.hpp"

#include <algorithm>
#include <cmath>

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
  explicit ExplicitSolverImpl(Scene<Dim>& scene) : scene_(scene) {
    const auto& P = scene.particles;
    for (auto& r : reactions_)
      r.setZero();
    apic_ = scene.spec.solver.transfer == TransferScheme::Apic;
    // The scene starts C_p from the initial velocity field; a later stage keeps what the
    // previous one left.
    if (apic_ && scene.particles.affine_velocity.size() != static_cast<std::size_t>(P.size()))
      throw std::logic_error("APIC transfer without the points' affine velocities");
    update_stress(); // stress consistent with the initial F
  }

  void step(double dt) override {
    map_.update(scene_.grid, scene_.particles);
    size_node_arrays();
    if constexpr (Axisymmetric) {
      const auto& P = scene_.particles;
      radius_n_.resize(at(P.size()));
      for (std::size_t s = 0; s < radius_n_.size(); ++s)
        radius_n_[s] = P.x[s][0];
    }
    switch (scene_.spec.solver.scheme) {
    case UpdateScheme::USF:
      gather_mass_momentum();
      grid_velocity_from_momentum();
      update_kinematics_and_stress(dt);
      gather_forces();
      grid_acceleration(dt);
      particle_update(dt);
      break;
    case UpdateScheme::USL:
      gather_mass_momentum();
      gather_forces();
      grid_velocity_from_momentum();
      grid_acceleration(dt);
      particle_update(dt);
      update_kinematics_and_stress(dt);
      break;
    case UpdateScheme::MUSL:
      gather_mass_momentum();
      gather_forces();
      grid_velocity_from_momentum();
      grid_acceleration(dt);
      particle_update(dt);
      remap_velocity(); // velocity gradient from the updated particle velocities
      update_kinematics_and_stress(dt);
      break;
    }
  }

  double stable_dt(double cfl) const override {
    const auto& P = scene_.particles;
    double max_speed = 0;
    for (Index p = 0; p < P.size(); ++p) {
      const auto s = static_cast<std::size_t>(p);
      const double c = scene_.materials[static_cast<std::size_t>(P.material[s])]->wave_speed();
      max_speed = std::max(max_speed, c + P.v[s].norm());
    }
    return cfl * scene_.grid.cell_size() / max_speed;
  }

  Energies energies() const override { return particle_energies(scene_, true); }

  FaceReactions reactions() const override { return reactions_; }
  Index active_nodes() const override { return map_.node_count(); }

  std::optional<StateViolation> grid_violation() const override {
    if (auto v = find_node_violation<Dim>(map_.nodes(), velocity_, "grid velocity"))
      return v;
    return find_node_violation<Dim>(map_.nodes(), acceleration_, "grid acceleration");
  }

  // The map and the grid arrays are rebuilt every step: nothing is kept per point.
  void particles_changed() override {}

private:
  Index node_count() const { return map_.node_count(); }
  V node_position(Index n) const { return map_.nodes().position(n); }

  // The step's node arrays, one entry per active node, and the faces' conditions on them.
  void size_node_arrays() {
    const auto nn = at(node_count());
    mass_.resize(nn);
    momentum_.resize(nn);
    force_.resize(nn);
    velocity_.resize(nn);
    acceleration_.resize(nn);
    held_.resize(nn);
    reaction_face_.resize(nn);
    for (Index n = 0; n < node_count(); ++n) {
      const auto ijk = map_.nodes().ijk(n);
      held_[at(n)] = scene_.face_conditions.held(ijk);
      reaction_face_[at(n)] = scene_.face_conditions.reaction_faces(ijk);
    }
  }

  // The particle's velocity field evaluated at a node: v_p, plus C_p (x_i - x_p) with APIC.
  V particle_velocity_at(Index p, const V& xi) const {
    const auto& P = scene_.particles;
    if (!apic_)
      return P.v[at(p)];
    return P.v[at(p)] + P.affine_velocity[at(p)] * (xi - P.x[at(p)]);
  }
  static std::size_t at(Index i) { return static_cast<std::size_t>(i); }

  void gather_mass_momentum() {
    const auto& P = scene_.particles;
    parallel_for(node_count(), [&](Index n) {
      double m = 0;
      V mv = V::Zero();
      const V xi = node_position(n);
      map_.for_each_particle_of(n, [&](Index p, double w, const V&) {
        m += w * P.mass[at(p)];
        mv += (w * P.mass[at(p)]) * particle_velocity_at(p, xi);
      });
      mass_[at(n)] = m;
      momentum_[at(n)] = mv;
    });
  }

  // Internal force -sum V sigma grad(N) plus external point forces, gravity and tractions.
  void gather_forces() {
    const auto& P = scene_.particles;
    const V g = head<Dim>(scene_.spec.gravity);
    parallel_for(node_count(), [&](Index n) {
      V f = V::Zero();
      map_.for_each_particle_of(n, [&](Index p, double w, const V& grad) {
        const auto s = at(p);
        const M sigma = P.stress[s].template topLeftCorner<Dim, Dim>();
        f -= P.volume[s] * (sigma * grad);
        if constexpr (Axisymmetric)
          f[0] -= P.volume[s] * P.stress[s](2, 2) * w / radius_n_[s];
        f += w * (P.external_force[s] + P.mass[s] * g);
      });
      force_[at(n)] = f;
    });
    for (const SurfaceLoad<Dim>& load : scene_.surface_loads)
      for_each_surface_load_node<Dim>(map_.nodes(), P, load, map_.stencil(load.particle).start,
                                      Shape::kWidth,
                                      [&](Index n, double w) { force_[at(n)] += w * load.force; });
  }

  void constrain(Index n, V& vec) const {
    const std::uint8_t mask = held_[at(n)];
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
    for (Index n = 0; n < node_count(); ++n) {
      if (mass_[at(n)] <= 0.0) {
        velocity_[at(n)].setZero();
        continue;
      }
      velocity_[at(n)] = momentum_[at(n)] / mass_[at(n)];
      constrain(n, velocity_[at(n)]);
    }
  }

  // a = f / m with constraints; the reaction on a constrained component is what holds it: -f.
  void grid_acceleration(double dt) {
    for (auto& r : reactions_)
      r.setZero();
    for (Index n = 0; n < node_count(); ++n) {
      const auto s = at(n);
      for (int d = 0; d < Dim; ++d)
        if (const int face = reaction_face_[s][static_cast<std::size_t>(d)]; face >= 0)
          reactions_[static_cast<std::size_t>(face)][d] -= force_[s][d];
      if (mass_[s] <= 0.0) {
        acceleration_[s].setZero();
        continue;
      }
      acceleration_[s] = force_[s] / mass_[s];
      constrain(n, acceleration_[s]);
      velocity_[s] += dt * acceleration_[s];
    }
  }

  // FLIP/PIC blend of the particle velocity, or APIC's velocity and affine matrix; positions
  // move with the updated grid velocity.
  void particle_update(double dt) {
    auto& P = scene_.particles;
    if (apic_) {
      old_x_.resize(at(P.size()));
      parallel_for(P.size(), [&](Index p) { apic_update(p, dt); });
      return;
    }
    const double flip = scene_.spec.solver.flip;
    parallel_for(P.size(), [&](Index p) {
      V a = V::Zero(), v_new = V::Zero();
      map_.for_each_node_of(p, [&](Index n, double w, const V&) {
        a += w * acceleration_[at(n)];
        v_new += w * velocity_[at(n)];
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
  void apic_update(Index p, double dt) {
    auto& P = scene_.particles;
    const auto s = at(p);
    V v_new = V::Zero();
    M B = M::Zero();
    map_.for_each_node_of(p, [&](Index n, double w, const V&) {
      v_new += w * velocity_[at(n)];
      B += w * velocity_[at(n)] * (node_position(n) - P.x[s]).transpose();
    });
    const double h = scene_.grid.cell_size();
    M C = M::Zero();
    if constexpr (!tensor_product<Shape>()) {
      // CPDI: D_p = sum w (x_i - x_p)(x_i - x_p)^T is a full matrix (the sheared voxel).
      M D = M::Zero();
      map_.for_each_node_of(p, [&](Index n, double w, const V&) {
        const V r = node_position(n) - P.x[s];
        D += w * r * r.transpose();
      });
      C = B * D.inverse();
    } else {
      const auto& st = map_.stencil(p);
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
    const auto& P = scene_.particles;
    parallel_for(node_count(), [&](Index n) {
      if (mass_[at(n)] <= 0.0) {
        velocity_[at(n)].setZero();
        return;
      }
      V mv = V::Zero();
      const V xi = node_position(n);
      map_.for_each_particle_of(n, [&](Index p, double w, const V&) {
        const V v =
            apic_ ? V(P.v[at(p)] + P.affine_velocity[at(p)] * (xi - old_x_[at(p)])) : P.v[at(p)];
        mv += (w * P.mass[at(p)]) * v;
      });
      velocity_[at(n)] = mv / mass_[at(n)];
      constrain(n, velocity_[at(n)]);
    });
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
    parallel_for(P.size(), [&](Index p) {
      M L = M::Zero();
      [[maybe_unused]] double v_r = 0; // the radial velocity at the point (axisymmetry)
      map_.for_each_node_of(p, [&](Index n, double w, const V& grad) {
        L += velocity_[at(n)] * grad.transpose();
        if constexpr (Axisymmetric)
          v_r += w * velocity_[at(n)][0];
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

  void update_stress() {
    auto& P = scene_.particles;
    for (std::size_t m = 0; m < scene_.materials.size(); ++m)
      scene_.materials[m]->update_stress(scene_.particles_of_material[m], P.F, P.stress);
  }

  Scene<Dim>& scene_;
  ParticleGridMap<Dim, Shape> map_;
  std::vector<double> mass_;
  std::vector<V> momentum_, force_, velocity_, acceleration_;
  std::vector<std::uint8_t> held_;                          ///< per node: FaceConditions::held
  std::vector<std::array<std::int8_t, Dim>> reaction_face_; ///< per node and component
  std::vector<V> old_x_; // APIC: the points' positions at the start of the step (MUSL's remap)
  std::vector<double> radius_n_; // axisymmetry: the points' radii at the start of the step
  FaceReactions reactions_{};
  bool apic_ = false;
};

/// ExplicitSolverImpl of one dimension, as a template of the shape function alone.
template <int Dim, bool Axisymmetric> struct ExplicitIn {
  template <class Shape> using Solver = ExplicitSolverImpl<Dim, Shape, Axisymmetric>;
};

} // namespace

template <int Dim> std::unique_ptr<ExplicitSolver> make_explicit_solver(Scene<Dim>& scene) {
  if constexpr (Dim == 2)
    if (scene.spec.geometry == Geometry::Axisymmetric)
      return make_for_shape<ExplicitSolver, ExplicitIn<2, true>::template Solver>(
          scene.spec.solver.shape, scene);
  return make_for_shape<ExplicitSolver, ExplicitIn<Dim, false>::template Solver>(
      scene.spec.solver.shape, scene);
}

template std::unique_ptr<ExplicitSolver> make_explicit_solver<2>(Scene<2>&);
template std::unique_ptr<ExplicitSolver> make_explicit_solver<3>(Scene<3>&);

} // namespace talus
