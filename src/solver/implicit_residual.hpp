#pragma once
// The out-of-balance force of an implicit step at a trial increment, per share of the points
// on the share's DofMap: the loads (and Newmark's inertia) on the unknowns the share owns, its
// points' internal forces, and the ghost-penalty forces of the faces it assembles; and the
// nodal increments all of them are computed from. A view of the step: it holds references
// only, and is made where it is needed.
#include "implicit_step_setup.hpp"
#include "implicit_trial_state.hpp"
#include "point_stencil.hpp"
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

  /// The pore pressure increment of node n (consolidation): s x from its unknown, a drained
  /// node's held increment, zero on a node without either.
  double pressure_increment(const DofMap& map, Index n, const Eigen::VectorXd& du) const {
    const Index dof = map.overlap_dof_at(n, map.layout().offset(step_.pressure_field));
    return dof >= 0 ? step_.consolidation->pressure_unit * du[dof]
                    : step_.node.prescribed_dp[at(n)];
  }

  /// Calls f(node, r) with point p's mass-balance terms (consolidation.hpp) on its stencil's
  /// nodes, at the trial state.
  template <class F> void for_each_mass_balance(Index p, F&& f) const {
    const auto s = at(p);
    const auto& c = *step_.consolidation;
    const PointStencil<Dim, Shape> stencil(step_.map, p, Axisymmetric ? trial_.radius_n(s) : 1.0);
    const Mat3 dF = trial_.step_gradient(s);
    const BiotPoint<Dim, Axisymmetric, PointStencil<Dim, Shape>::kNodes> point{
        stencil.weights,
        stencil.grads,
        stencil.hoop,
        dF,
        c.flow[at(trial_.material(s))],
        trial_.volume_n(s),
        c.flow_time,
        c.pressure_unit,
        trial_.pressure_increment(s),
        trial_.pressure_gradient(s),
        c.gravity_head};
    const auto r = point.residual();
    for (int k = 0; k < r.size(); ++k)
      f(stencil.nodes[at(k)], r[k]);
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
    if (step_.consolidation) {
      const int offset = map.layout().offset(step_.pressure_field);
      for (Index p = share.begin; p < share.end; ++p)
        for_each_mass_balance(p, [&](Index n, double value) {
          if (const Index dof = map.overlap_dof_at(n, offset); dof >= 0)
            r[dof] += value;
        });
      step_.projection.for_each_residual(
          share, step_.map, trial_.points(),
          [&](Index p) { return trial_.pressure_increment(at(p)); },
          step_.consolidation->pressure_unit,
          [&](Index n, double value) {
            if (const Index dof = map.overlap_dof_at(n, offset); dof >= 0)
              r[dof] += value;
          });
    }
  }

private:
  const ImplicitStepSetup<Dim, Shape, Axisymmetric>& step_;
  const ImplicitTrialState<Dim, Shape, Axisymmetric>& trial_;
  bool dynamic_ = false;
  double dt_ = 1;
};

} // namespace talus
