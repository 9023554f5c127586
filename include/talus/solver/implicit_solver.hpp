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
//
// The dimension is the scene's: plane strain (Dim = 2, F33 = 1) or 3D, one source for both.
//
// Assembly by shares: R and K are sums of terms that each belong to one share of the points
// (ParticleShare), assembled on the share's overlapping DOF map (DofMap) in local ids:
//   - its points' internal forces and tangent blocks K_p = V0 B^T A B;
//   - the node terms (loads, Newmark inertia) of the nodes it owns;
//   - the ghost-penalty faces whose first on-face node it owns.
// Scattered to global DOFs and summed over the shares they give the one-process R and K (the
// serial solver is one share owning every node). A distributed run (scene.distributed()) is
// one share per rank: the step's preparation is the rank's, made whole by halo sums
// (implicit_step_setup.hpp), the shares are added by a Tpetra Export (ADD) and solved by Belos
// with MueLu (distributed_linear_solver.hpp), and Newton's vectors hold the owned unknowns.
#include "talus/linalg/linear_solver.hpp"
#include "talus/scene/scene.hpp"
#include "talus/solver/explicit_solver.hpp"
#include "talus/solver/newton.hpp"

#include <array>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace talus {

/// Wall time by phase, summed over a solver's steps (summary.json `seconds_*`). The phases do
/// not overlap; with the stepping loop's other work (output, splitting, the stepper) they add up
/// to the loop's time.
struct ImplicitTimings {
  double step_setup = 0;        ///< per step: connectivity, unknowns, loads, ghost faces
  double material = 0;          ///< per iterate: dF, F and the material's response
  double residual_assembly = 0; ///< per iterate: nodal forces from the points' stresses
  double tangent_assembly = 0;  ///< per iterate: point blocks into the matrix (structure too)
  double analysis = 0;          ///< linear solver: symbolic analyses
  double factorization = 0;     ///< linear solver: numeric factorisations (preconditioners)
  double solve = 0;             ///< linear solver: solves
  double commit = 0;            ///< per step: moving the points with the converged increment
};

/// The phases under their summary.json keys (seconds_step_setup, seconds_material, ...).
inline std::array<std::pair<const char*, double>, 8> implicit_phases(const ImplicitTimings& t) {
  return {{{"seconds_step_setup", t.step_setup},
           {"seconds_material", t.material},
           {"seconds_residual_assembly", t.residual_assembly},
           {"seconds_tangent_assembly", t.tangent_assembly},
           {"seconds_analysis", t.analysis},
           {"seconds_factorization", t.factorization},
           {"seconds_solve", t.solve},
           {"seconds_commit", t.commit}}};
}

class ImplicitSolver {
public:
  virtual ~ImplicitSolver() = default;
  /// Tries the step that takes the load factor to `lambda_end` and the prescribed
  /// displacements to the fraction `ramp_end` of their final values, over the time step dt.
  /// On convergence the particle state is advanced; otherwise it is left untouched.
  virtual NewtonReport step(double lambda_end, double ramp_end, double dt) = 0;
  virtual Energies energies() const = 0;
  /// Support reactions per grid face at the last converged step, N (per unit thickness).
  virtual FaceReactions reactions() const = 0;
  /// The force each prescribed region needs (same order as the case's `prescribed`), N.
  virtual std::vector<Vec3> prescribed_reactions() const = 0;
  virtual Index active_nodes() const = 0;
  virtual Index unknowns() const = 0;
  virtual ImplicitTimings timings() const = 0;
  /// The tangent of the last Newton iteration (empty before the first): `talus run
  /// --dump-tangent` writes it for benchmarking the linear solver on a real system.
  virtual const SparseMatrix& last_tangent() const = 0;
  /// From now on, measure load_compliance() after every converged quasi-static step: one more
  /// solve with the last factorisation per step (talus fos's failure criterion).
  virtual void measure_load_compliance() = 0;
  /// The compliance of the last converged state under the external load f of its step,
  /// f . K^-1 f / |f|^2 with K the consistent tangent there; NaN while nothing was measured
  /// (not asked for, a dynamic analysis, no load, or a step that needed no Newton iteration).
  virtual double load_compliance() const = 0;
  /// The linear solver backend in use (the case's choice, or the automatic one), e.g. "umfpack".
  virtual std::string linear_solver() const = 0;
  /// The scene's points were added to (splitting, core/splitting.hpp) after a converged step:
  /// resizes the per-point trial state.
  virtual void particles_changed() = 0;

  /// What the solver carries from one step to the next beyond the scene's points: a
  /// checkpoint keeps it, a resumed run hands it to continue_from() before its first step.
  struct Continuation {
    double prescribed_fraction = 0; ///< of the prescribed displacements, reached so far
    bool line_search_first = false; ///< the last step converged with the line search
  };
  virtual Continuation continuation() const = 0;
  virtual void continue_from(const Continuation& c) = 0;
};

/// `prescribed_fraction_reached`: the fraction of the prescribed displacements already applied
/// (a later stage of a staged analysis starts at 1: the regions hold their final position).
template <int Dim>
std::unique_ptr<ImplicitSolver> make_implicit_solver(Scene<Dim>& scene,
                                                     double prescribed_fraction_reached = 0.0);

} // namespace talus
