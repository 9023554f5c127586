#pragma once
// The out-of-balance force of an implicit step at a trial increment, per share of the points
// on the share's DofMap: the loads (and Newmark's inertia) on the unknowns the share owns, its
// points' internal forces, and the ghost-penalty forces of the faces it assembles; and the
// nodal increments all of them are computed from. A view of the step: it holds references
// only, and is made where it is needed.
#include "implicit_step_setup.hpp"
#include "implicit_trial_state.hpp"
#include "talus/linalg/dof_map.hpp"

#include <Eigen/Core>

namespace talus {

template <int Dim, class Shape, bool Axisymmetric> class ImplicitResidual {
  using V = Vec<Dim>;
  using Ghost = GhostPenalty<Dim>;

public:
  /// dt: the step's length (Newmark's inertia with `dynamic`).
  ImplicitResidual(const ImplicitStepSetup<Dim, Shape, Axisymmetric>& step,
                   const ImplicitTrialState<Dim, Shape, Axisymmetric>& trial, bool dynamic,
                   double dt)
      : step_(step), trial_(trial), dynamic_(dynamic), dt_(dt) {}

  /// The local unknown of displacement component a of node n in the share's map; refuses a
  /// node outside it.
  static Index displacement_dof(const DofMap& map, Index n, int a) {
    return map.overlap_dof_at(n, map.layout().offset(NodeLayout::kDisplacement) + a);
  }

  /// The increment of node n: unknowns from du (local ids of map), prescribed components from
  /// the ramp, zero for held components.
  V node_increment(const DofMap& map, Index n, const Eigen::VectorXd& du) const {
    V u;
    for (int a = 0; a < Dim; ++a) {
      const Index dof = displacement_dof(map, n, a);
      u[a] = dof >= 0 ? du[dof] : step_.node.prescribed_du[at(n)][a];
    }
    return u;
  }

  /// Newmark's a_{n+1} = 4/dt^2 (du - dt v_n) - a_n of a (global) unknown.
  double newmark_acceleration(Index dof, double du) const {
    return 4.0 / (dt_ * dt_) * (du - dt_ * step_.grid_v[at(dof)]) - step_.grid_a[at(dof)];
  }

  /// Calls f(node, component, force) with the ghost-penalty forces G du of every stabilised
  /// face the share assembles (`assembles(face)`; prescribed components enter with their
  /// increments, held ones as zero).
  template <class Assembles, class F>
  void for_each_ghost_force(const DofMap& map, const Eigen::VectorXd& du, Assembles&& assembles,
                            F&& f) const {
    const auto& G = Ghost::face_matrix();
    for (const auto& face : step_.ghost.faces()) {
      if (!assembles(face))
        continue;
      Eigen::Matrix<double, Ghost::kFaceNodes, Dim> u;
      for (int k = 0; k < Ghost::kFaceNodes; ++k)
        u.row(k) = node_increment(map, face.nodes[at(k)], du).transpose();
      const Eigen::Matrix<double, Ghost::kFaceNodes, Dim> forces = face.stiffness * G * u;
      for (int k = 0; k < Ghost::kFaceNodes; ++k)
        for (int a = 0; a < Dim; ++a)
          f(face.nodes[at(k)], a, forces(k, a));
    }
  }

  /// The share's residual at the trial state (evaluated at du): node terms of its owned
  /// unknowns (local ids [0, owned_count)), its points' internal forces and the ghost-penalty
  /// forces of its faces.
  template <class Assembles>
  void assemble(const ParticleShare& share, const DofMap& map, const Eigen::VectorXd& du,
                Assembles&& assembles, Eigen::VectorXd& r) const {
    r.setZero(map.overlap_count());
    const auto& gids = map.overlap_gids();
    for (Index l = 0; l < map.owned_count(); ++l) {
      const Index gid = gids[at(l)];
      r[l] = -step_.external[gid];
      if (dynamic_) // Newmark: M a_{n+1}
        r[l] += step_.dof_mass[at(gid)] * newmark_acceleration(gid, du[l]);
    }
    for (Index p = share.begin; p < share.end; ++p)
      trial_.for_each_internal_force(step_.map, p, [&](Index n, double, const V& f) {
        for (int a = 0; a < Dim; ++a)
          if (const Index dof = displacement_dof(map, n, a); dof >= 0)
            r[dof] += f[a];
      });
    for_each_ghost_force(map, du, assembles, [&](Index n, int a, double f) {
      if (const Index dof = displacement_dof(map, n, a); dof >= 0)
        r[dof] += f;
    });
  }

private:
  const ImplicitStepSetup<Dim, Shape, Axisymmetric>& step_;
  const ImplicitTrialState<Dim, Shape, Axisymmetric>& trial_;
  bool dynamic_ = false;
  double dt_ = 1;
};

} // namespace talus
