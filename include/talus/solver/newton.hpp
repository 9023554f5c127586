#pragma once
// Newton's method for R(x) = 0 driven by SUNDIALS KINSOL (line search, convergence tests,
// iteration cap), with the linear systems solved by our LinearSolver backends through a
// custom SUNLinearSolver. The caller provides the residual and the consistent Jacobian.
#include "talus/core/types.hpp"
#include "talus/linalg/linear_solver.hpp"
#include "talus/parallel/communicator.hpp"

#include <Eigen/Core>
#include <string>
#include <vector>

namespace talus {

class NonlinearSystem {
public:
  virtual ~NonlinearSystem() = default;
  /// The unknowns this process holds (all of them, or in a distributed run the owned ones).
  virtual Index size() const = 0;
  /// The ranks the unknowns are spread over (KINSOL's vectors then take their norms and dot
  /// products over all of them; every call below is collective, and residual() must agree
  /// across the ranks on whether x is admissible). Null: one process.
  virtual const Communicator* communicator() const { return nullptr; }
  /// The unknowns of all ranks.
  virtual Index global_size() const { return size(); }
  /// R(x). Returns false when x is not admissible (a material update failed, det F <= 0):
  /// KINSOL then shortens the step, and the load stepper cuts back if that does not help.
  virtual bool residual(const Eigen::VectorXd& x, Eigen::VectorXd& r) = 0;
  /// The Jacobian dR/dx at x, called after residual(x).
  virtual const SparseMatrix& jacobian(const Eigen::VectorXd& x) = 0;
  /// True when the Jacobian's sparsity pattern differs from the one the linear solver was last
  /// analysed for (by any earlier solve), so it must redo its symbolic analysis.
  virtual bool pattern_changed() const = 0;
  /// Called once the linear solver has analysed the current Jacobian's pattern.
  virtual void pattern_analysed() = 0;
  /// What unknown `i` of this process is, for a failure that names it (a zero pivot): text
  /// that follows the linear solver's message, or empty.
  virtual std::string describe_unknown(Index /*i*/) const { return {}; }
};

struct NewtonOptions {
  /// Converged when max_i |R_i| <= residual_tolerance * residual_scale.
  double residual_tolerance = 1e-8;
  double residual_scale = 1.0; ///< a force scale of the problem (e.g. the external load norm)
  /// Converged also when the scaled step max_i |dx_i| / step_scale falls below this.
  double step_tolerance = 1e-13;
  double step_scale = 1.0;
  /// Iterations an attempt always gets. Beyond them it goes on while it makes progress (the
  /// residual down by at least a quarter over the last `progress_window` iterates), up to
  /// `extension` times this many: a hard step that converges slowly is not cut short, one that
  /// stagnates is.
  int max_iterations = 25;
  int extension = 4;
  int progress_window = 10;
  bool line_search = true;
};

struct NewtonReport {
  bool converged = false;
  int iterations = 0;
  int residual_evaluations = 0;
  int linear_solves = 0;
  int linear_iterations = 0; ///< summed over the solves (1 per solve for a direct solver)
  int factorizations = 0;
  int symbolic_analyses = 0;
  /// max_i |R_i| / residual_scale at each Newton iterate, the converged one last.
  std::vector<double> residual_history;
  /// The history of an abandoned first attempt when the caller retried the step the other
  /// way (plain Newton and line search); empty otherwise.
  std::vector<double> abandoned_history;
  bool abandoned_line_search = false; ///< the abandoned attempt was the line search
  std::string message;                ///< KINSOL's reason (or the stagnation) when not converged
  /// Wall time inside the linear solver: symbolic analyses, numeric factorisations, solves.
  double seconds_analysis = 0, seconds_factorization = 0, seconds_solve = 0;
};

/// Solves R(x) = 0 from the initial guess in x (overwritten with the solution).
NewtonReport solve_newton(NonlinearSystem& system, LinearSolver& linear_solver, Eigen::VectorXd& x,
                          const NewtonOptions& options);

} // namespace talus
