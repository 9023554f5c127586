#pragma once
// A converged implicit step committed to the points: they move with the grid's increment and
// keep the trial state (F, stress, volume) as their own; in dynamics their velocity and
// acceleration follow Newmark's grid values (FLIP blended with PIC by solver.flip), in
// quasi-static steps the velocity is the pseudo-rate of the step. Returns each node's internal
// force on the way, from which the step's reactions follow (implicit_reactions.hpp).
#include "implicit_residual.hpp"
#include "implicit_step_setup.hpp"
#include "implicit_trial_state.hpp"

#include <vector>

namespace talus {

template <int Dim, class Shape, bool Axisymmetric>
std::vector<Vec<Dim>>
commit_points(Scene<Dim>& scene, const ImplicitStepSetup<Dim, Shape, Axisymmetric>& step,
              const ImplicitTrialState<Dim, Shape, Axisymmetric>& trial,
              const ImplicitResidual<Dim, Shape, Axisymmetric>& balance, const DofMap& map,
              const Eigen::VectorXd& du, double dt, bool dynamic) {
  using V = Vec<Dim>;
  auto& P = scene.particles;
  const double flip = scene.spec.solver.flip;
  std::vector<V> internal(step.node.load.size(), V::Zero());
  for (Index p = 0; p < P.size(); ++p) {
    const auto s = at(p);
    V dx = V::Zero();
    trial.for_each_internal_force(step.map, p, [&](Index n, double w, const V& f) {
      internal[at(n)] += f;
      dx += w * balance.node_increment(map, n, du);
    });
    const Mat3& F = trial.F(s);
    const double J = F.determinant();
    P.F[s] = F;
    P.stress[s] = trial.kirchhoff(s) / J;
    if (!P.pore_pressure.empty()) { // the material's stress is the effective one
      P.pore_pressure[s] = trial.pore_pressure(s);
      P.stress[s].diagonal().array() -= trial.pore_stress(s);
    }
    P.volume[s] = J * P.volume0[s];
    P.x[s] += dx;
    if (!dynamic) {
      P.v[s] = dx / dt; // rate of the pseudo-time, reported for output only
      continue;
    }
    // FLIP increments of the Newmark grid velocity, blended with its PIC interpolation (PIC
    // damps the particle velocity noise that the grid cannot see); acceleration from the grid.
    // A constrained component moves with its prescribed increment (zero on a fixed face).
    V dv = V::Zero(), v_grid = V::Zero(), a = V::Zero();
    step.map.for_each_node_of(p, [&](Index n, double w, const V&) {
      for (int c = 0; c < Dim; ++c) {
        const Index dof = step.displacement_dof(n, c);
        if (dof < 0) {
          v_grid[c] += w * step.node.prescribed_du[at(n)][c] / dt;
          continue;
        }
        const double a_new = balance.newmark_acceleration(dof, du[dof]);
        a[c] += w * a_new;
        const double dv_node = 0.5 * dt * (step.grid_a[at(dof)] + a_new);
        dv[c] += w * dv_node;
        v_grid[c] += w * (step.grid_v[at(dof)] + dv_node);
      }
    });
    P.v[s] = flip * (P.v[s] + dv) + (1.0 - flip) * v_grid;
    P.acceleration[s] = a;
  }
  for (std::size_t m = 0; m < scene.materials.size(); ++m)
    scene.materials[m]->commit(scene.particles_of_material[m]);
  return internal;
}

} // namespace talus
