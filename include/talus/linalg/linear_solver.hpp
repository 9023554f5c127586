#pragma once
// Sparse linear solvers behind one interface, for the implicit Newton solve K du = -R.
// The symbolic analysis (ordering, symbolic factorisation, preconditioner structure) is done by
// analyze() and reused by factorize() as long as the sparsity pattern does not change.
#include "talus/core/errors.hpp"

#include <Eigen/SparseCore>

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

namespace talus {

using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

enum class LinearSolverKind {
  Cholmod,       ///< SuiteSparse CHOLMOD, sparse Cholesky (symmetric positive definite)
  Umfpack,       ///< SuiteSparse UMFPACK, sparse LU (general)
  Klu,           ///< SuiteSparse KLU, sparse LU for circuit-like/FE matrices (general)
  EigenCg,       ///< Eigen conjugate gradients, incomplete-Cholesky preconditioner (SPD)
  EigenBicgstab, ///< Eigen BiCGSTAB, incomplete-LU (ILUT) preconditioner (general)
  TrilinosCg,    ///< Trilinos Belos CG with a MueLu (default) or Ifpack2 preconditioner (SPD)
  TrilinosGmres, ///< Trilinos Belos GMRES with a MueLu or Ifpack2 preconditioner (general)
};

/// A direct factorisation met a zero (or, Cholesky, a non-positive) pivot. `unknown()` is the
/// row and column of the matrix as given whose pivot it was, so that the caller can say which
/// node and component has no stiffness; -1 when the backend does not tell.
class SingularPivot : public NumericalError {
public:
  SingularPivot(long long unknown, const std::string& what)
      : NumericalError(what), unknown_(unknown) {}
  long long unknown() const { return unknown_; }

private:
  long long unknown_;
};

struct LinearSolverOptions {
  LinearSolverKind kind = LinearSolverKind::Cholmod;
  double tolerance = 1e-10;   ///< iterative solvers: relative residual ||b - Ax|| / ||b||
  int max_iterations = 2000;  ///< iterative solvers
  std::string preconditioner; ///< Trilinos: "muelu" (default) or "ifpack2"; ignored otherwise
};

struct LinearSolveStats {
  int iterations = 0;           ///< 1 for direct solvers
  double relative_residual = 0; ///< ||b - A x|| / ||b|| measured after the solve
};

class LinearSolver {
public:
  virtual ~LinearSolver() = default;
  virtual std::string name() const = 0;
  /// True when the method needs a symmetric (positive definite) matrix.
  virtual bool requires_symmetric() const = 0;
  /// Symbolic phase for A's sparsity pattern.
  virtual void analyze(const SparseMatrix& A) = 0;
  /// Numeric phase for A (same pattern as the last analyze()). Throws SingularPivot when the
  /// matrix is singular or (Cholesky) not positive definite.
  virtual void factorize(const SparseMatrix& A) = 0;
  /// Solves A x = b with the last factorised A; throws NumericalError if an iterative method
  /// does not reach its tolerance.
  virtual LinearSolveStats solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) = 0;
  /// Whether the solver builds a coarse space from the operator's near-null space (algebraic
  /// multigrid); set_near_null_space() is then worth calling before the next factorize().
  virtual bool uses_near_null_space() const { return false; }
  /// The vectors the operator (nearly) annihilates, one column per mode and one row per unknown:
  /// for elasticity the rigid-body motions. Kept until replaced.
  virtual void set_near_null_space(Eigen::MatrixXd /*modes*/) {}
};

/// True when two compressed sparse matrices (any Eigen storage order) have the same size and
/// sparsity pattern: the test for reusing a symbolic analysis.
template <class SparseA, class SparseB>
bool same_sparsity_pattern(const SparseA& a, const SparseB& b) {
  if (a.rows() != b.rows() || a.cols() != b.cols() || a.nonZeros() != b.nonZeros() ||
      a.outerSize() != b.outerSize())
    return false;
  const auto n = static_cast<std::size_t>(a.outerSize()) + 1;
  const auto nnz = static_cast<std::size_t>(a.nonZeros());
  return std::equal(a.outerIndexPtr(), a.outerIndexPtr() + n, b.outerIndexPtr()) &&
         std::equal(a.innerIndexPtr(), a.innerIndexPtr() + nnz, b.innerIndexPtr());
}

/// 3D systems with at least this many unknowns are solved by Belos with MueLu (CG and the
/// rigid-body modes for a symmetric tangent, GMRES for a nonsymmetric one) unless the case
/// names a solver. Measured on the 3D cantilever (symmetric), the direct and the iterative
/// solve take the same time at 7.1k unknowns and CG is 1.6x faster at 15.7k, 3.9x at 49k, 9.6x
/// at 112k; on the 3D slope (Mohr-Coulomb, psi = 0, F-bar: nonsymmetric) GMRES took 258 s for
/// the first two load steps at 13.5k unknowns where UMFPACK had not finished the second after
/// 14 minutes (docs/architecture.md, "Linear solvers in 3D").
inline constexpr long long kIterativeUnknowns3d = 10000;

/// The backend a case gets when it names none: CHOLMOD for a symmetric tangent, UMFPACK for a
/// nonsymmetric one, and in 3D from kIterativeUnknowns3d unknowns on trilinos_cg or
/// trilinos_gmres when the binary has Trilinos.
LinearSolverKind automatic_linear_solver(bool symmetric, int dimension, long long unknowns);

/// The backend an implicit run uses on one rank: `chosen` (a case's solver.linear_solver), or
/// automatic_linear_solver when it is empty. Throws std::invalid_argument for an unknown name.
LinearSolverKind implicit_linear_solver(const std::string& chosen, bool symmetric, int dimension,
                                        long long unknowns);

/// Throws std::invalid_argument for a kind not built into this binary.
std::unique_ptr<LinearSolver> make_linear_solver(const LinearSolverOptions& options);

/// Names of the backends this binary was built with (for `talus info`), e.g. "cholmod".
std::vector<std::string> available_linear_solvers();

/// Case-file name <-> kind: cholmod, umfpack, klu, eigen_cg, eigen_bicgstab, trilinos_cg,
/// trilinos_gmres.
std::string to_string(LinearSolverKind kind);
bool parse_linear_solver_kind(const std::string& name, LinearSolverKind& kind);

} // namespace talus
