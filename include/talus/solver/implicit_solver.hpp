#pragma once
// Implicit MPM, quasi-static or dynamic (Newmark, beta = 1/4, gamma = 1/2, on the grid with
// lumped mass: R gains M a_{n+1}, a_{n+1} = 4/dt^2 (du - dt v_n) - a_n, and K gains
// 4 M / dt^2). Each step solves for the grid displacement increment du that
// puts the material points in equilibrium with the loads scaled to the step's end,
//   R(du) = f_int(du) - lambda f_ext = 0,
// by Newton's method (KINSOL) with the consistent tangent. The increment is measured from the
// configuration at the start of the step (updated Lagrangian): dF = I + grad(du), F = dF F_n,
// and f_int,i = sum_p V0_p tau_p dF_p^-T grad N_i(x_p^n), whose derivative contains both the
// material and the geometric (initial-stress) stiffness.
#include "talus/core/scene.hpp"
#include "talus/solver/explicit_solver.hpp"
#include "talus/solver/newton.hpp"

#include <array>
#include <memory>
#include <vector>

namespace talus {

class ImplicitSolver {
public:
  virtual ~ImplicitSolver() = default;
  /// Tries the step that takes the load factor to `lambda_end` and the prescribed
  /// displacements to the fraction `ramp_end` of their final values, over the time step dt.
  /// On convergence the particle state is advanced; otherwise it is left untouched.
  virtual NewtonReport step(double lambda_end, double ramp_end, double dt) = 0;
  virtual Energies energies() const = 0;
  /// Support reactions per grid face at the last converged step, N (per unit thickness).
  virtual std::array<Vec2, kFaceCount> reactions() const = 0;
  /// The force each prescribed region needs (same order as the case's `prescribed`), N.
  virtual std::vector<Vec2> prescribed_reactions() const = 0;
  virtual Index active_nodes() const = 0;
  virtual Index unknowns() const = 0;
  virtual double seconds_particle_update() const = 0;
};

std::unique_ptr<ImplicitSolver> make_implicit_solver(Scene<2>& scene);

} // namespace talus
