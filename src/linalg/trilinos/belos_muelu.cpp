#include "belos_muelu.hpp"

#include "talus/core/errors.hpp"

#include <BelosLinearProblem.hpp>
#include <BelosSolverFactory.hpp>
#include <BelosSolverFactory_Tpetra.hpp>
#include <BelosTpetraAdapter.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace talus::detail {

Teuchos::ParameterList muelu_parameters(int ranks, long long rows) {
  constexpr int kCoarseMaxSize = 1000;
  Teuchos::ParameterList p;
  p.set("verbosity", std::string("none"));
  p.set("multigrid algorithm", std::string("sa"));
  p.set("number of equations", 1);
  p.set("max levels", 10);
  p.set("coarse: max size", kCoarseMaxSize);
  p.set("aggregation: type", std::string("uncoupled"));
  p.set("smoother: type", std::string("RELAXATION"));
  auto& smoother = p.sublist("smoother: params");
  smoother.set("relaxation: type", std::string("Symmetric Gauss-Seidel")); // symmetric: CG
  smoother.set("relaxation: sweeps", 1);
  // The coarsest level is solved exactly (KLU2). On several ranks that needs it on one rank:
  // Amesos2 on a coarse matrix spread over the ranks gave CG an indefinite preconditioner, and
  // smoothing the coarse level instead (4 symmetric Gauss-Seidel sweeps) took CG from 17 to 59
  // iterations on the 3D cantilever (15.7k unknowns). Zoltan2 repartitions the coarse levels,
  // by the unknowns' coordinates, to one rank per 4000 rows: 19 iterations there. The fine
  // level is never repartitioned, so a system small enough to be its own coarsest level is
  // smoothed there instead (a few hundred unknowns: the iterations hardly matter).
  const bool one_level = rows <= kCoarseMaxSize;
  p.set("repartition: enable", ranks > 1 && !one_level);
  if (ranks > 1 && !one_level) {
    p.set("repartition: partitioner", std::string("zoltan2"));
    p.set("repartition: start level", 1);
    p.set("repartition: min rows per proc", 4000);
  }
  if (ranks == 1 || !one_level) {
    p.set("coarse: type", std::string("KLU2"));
  } else {
    p.set("coarse: type", std::string("RELAXATION"));
    auto& coarse = p.sublist("coarse: params");
    coarse.set("relaxation: type", std::string("Symmetric Gauss-Seidel"));
    coarse.set("relaxation: sweeps", 4);
  }
  return p;
}

LinearSolveStats belos_solve(bool cg, const Teuchos::RCP<const OP>& A, const Teuchos::RCP<OP>& prec,
                             const Teuchos::RCP<MV>& X, const Teuchos::RCP<const MV>& B,
                             double tolerance, int max_iterations, const std::string& description) {
  auto params = Teuchos::parameterList();
  params->set("Convergence Tolerance", tolerance);
  params->set("Maximum Iterations", max_iterations);
  params->set("Verbosity", static_cast<int>(Belos::Errors));
  params->set("Implicit Residual Scaling", std::string("Norm of RHS"));
  if (!cg) {
    const int restart = std::max(1, std::min(max_iterations, 150));
    params->set("Num Blocks", restart);
    params->set("Maximum Restarts", max_iterations / restart + 1);
    params->set("Explicit Residual Scaling", std::string("Norm of RHS"));
  }
  Belos::SolverFactory<SC, MV, OP> factory;
  auto solver = factory.create(cg ? "CG" : "GMRES", params);
  auto problem = Teuchos::rcp(new Belos::LinearProblem<SC, MV, OP>(A, X, B));
  if (cg)
    problem->setLeftPrec(prec);
  else
    problem->setRightPrec(prec);

  std::vector<SC> b_norm(1), r_norm(1);
  B->norm2(Teuchos::ArrayView<SC>(b_norm));
  MV R(B->getMap(), 1);
  LinearSolveStats stats;
  // CG with a left preconditioner stops on the preconditioned residual, whose ratio to the
  // true one depends on the preconditioner (measured 4.7x with MueLu's smoothed coarse level on
  // two ranks). A pass that stops short asks the next for that much more, twice over.
  double asked = tolerance;
  for (int pass = 0; pass < 3; ++pass) {
    params->set("Convergence Tolerance", asked);
    solver->setParameters(params);
    try {
      problem->setProblem(); // (re)computes the initial residual from the current X
      solver->setProblem(problem);
      solver->solve();
    } catch (const std::exception& e) {
      throw NumericalError(fmt::format("{}: solver failed after {} iterations: {}", description,
                                       stats.iterations + solver->getNumIters(), e.what()));
    }
    stats.iterations += solver->getNumIters();
    A->apply(*X, R);
    R.update(1.0, *B, -1.0);
    R.norm2(Teuchos::ArrayView<SC>(r_norm));
    stats.relative_residual = r_norm[0] / b_norm[0];
    if (stats.relative_residual <= tolerance || stats.iterations >= max_iterations ||
        !std::isfinite(stats.relative_residual))
      break;
    asked *= 0.5 * tolerance / stats.relative_residual;
  }
  // A solve that stagnates within kStagnationFactor of the tolerance is accepted: round-off
  // bounds what CG can attain on a tangent whose nodes range from a sliver of mass to a full
  // cell (measured 2.0e-10 serial, 4.5e-10 on two ranks on the slender elastica's first step
  // at h = D/8, where 1e-10 was asked), and Newton's own residual test, not the linear
  // solver's, decides convergence: an inexact step slows Newton, it cannot end it wrongly.
  constexpr double kStagnationFactor = 100.0;
  if (!(stats.relative_residual <= kStagnationFactor * tolerance))
    throw NumericalError(fmt::format(
        "{}: did not reach the tolerance {:.3g}: {} iterations, ||b - Ax||/||b|| = {:.3e}",
        description, tolerance, stats.iterations, stats.relative_residual));
  return stats;
}

} // namespace talus::detail
