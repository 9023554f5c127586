// Eigen's preconditioned Krylov solvers: CG + incomplete Cholesky (SPD) and BiCGSTAB + ILUT.
//
// analyze() computes the preconditioner's fill-reducing ordering (analyzePattern), factorize()
// the incomplete factors. The solver keeps a compressed copy of A: Eigen's iterative solvers
// hold a reference to the matrix they were set up with, and the true residual is computed from it.
// Convergence is judged on the true relative residual ||b - Ax|| / ||b||; when the solver stops on
// its recursive residual but the true one is above the tolerance (rounding drift), the solve is
// restarted once from the current iterate.
#include "talus/core/errors.hpp"
#include "talus/linalg/linear_solver.hpp"

#include <Eigen/IterativeLinearSolvers>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

namespace talus {
namespace {

// CG reads only the lower triangle (A holds both): Eigen's full-matrix (Lower|Upper) product goes
// through its OpenMP path, measured 15x slower than this serial one on a loaded 2-core machine.
// Natural ordering for the incomplete Cholesky factor: AMD, Eigen's default, costs ~1.7x more CG
// iterations on grid matrices (211 vs 124 on a 141^2 Poisson problem), a known effect of
// minimum-degree orderings on incomplete factorisations.
using EigenCg = Eigen::ConjugateGradient<
    SparseMatrix, Eigen::Lower,
    Eigen::IncompleteCholesky<double, Eigen::Lower, Eigen::NaturalOrdering<int>>>;
using EigenBicgstab = Eigen::BiCGSTAB<SparseMatrix, Eigen::IncompleteLUT<double>>;

template <class Solver> class EigenIterativeSolver final : public LinearSolver {
public:
  EigenIterativeSolver(std::string name, bool symmetric, const LinearSolverOptions& options)
      : name_(std::move(name)), symmetric_(symmetric), tolerance_(options.tolerance),
        max_iterations_(options.max_iterations) {
    if (!(tolerance_ > 0.0) || max_iterations_ < 1) {
      throw std::invalid_argument(name_ + ": tolerance must be > 0 and max_iterations >= 1");
    }
    solver_.setTolerance(tolerance_);
    solver_.setMaxIterations(max_iterations_);
  }

  std::string name() const override { return name_; }
  bool requires_symmetric() const override { return symmetric_; }

  void analyze(const SparseMatrix& A) override {
    if (A.rows() != A.cols()) {
      throw std::invalid_argument(name_ + ": matrix is not square");
    }
    analyzed_ = false;
    factorized_ = false;
    A_ = A;
    A_.makeCompressed();
    if constexpr (std::is_same_v<Solver, EigenBicgstab>)
      // Eigen 3.4's IncompleteLUT::analyzePattern leaves its status unset and BiCGSTAB's
      // analyzePattern reads it (undefined behaviour, reported by UBSan); a full compute sets it.
      // It costs one extra incomplete factorisation per analysed pattern.
      solver_.compute(A_);
    else
      solver_.analyzePattern(A_);
    analyzed_ = true;
  }

  void factorize(const SparseMatrix& A) override {
    if (!analyzed_) {
      throw std::logic_error(name_ + ": factorize() before analyze()");
    }
    factorized_ = false;
    SparseMatrix copy = A;
    copy.makeCompressed();
    if (!same_sparsity_pattern(copy, A_)) {
      throw std::invalid_argument(name_ +
                                  ": factorize() with a sparsity pattern that differs from the "
                                  "one given to analyze()");
    }
    A_ = std::move(copy);
    solver_.factorize(A_);
    if (solver_.info() != Eigen::Success) {
      throw NumericalError(name_ + ": preconditioner construction failed");
    }
    factorized_ = true;
  }

  LinearSolveStats solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) override {
    if (!factorized_) {
      throw std::logic_error(name_ + ": solve() before a successful factorize()");
    }
    if (b.size() != A_.rows()) {
      throw std::invalid_argument(fmt::format(
          "{}: right-hand side has {} entries, matrix has {} rows", name_, b.size(), A_.rows()));
    }
    LinearSolveStats stats;
    const double bnorm = b.norm();
    if (bnorm == 0.0) {
      x.setZero(b.size());
      return stats;
    }
    Eigen::VectorXd result = Eigen::VectorXd::Zero(b.size());
    for (int pass = 0; pass < 2; ++pass) {
      solver_.setMaxIterations(max_iterations_ - stats.iterations);
      result = solver_.solveWithGuess(b, result);
      stats.iterations += static_cast<int>(solver_.iterations());
      stats.relative_residual = (b - A_ * result).norm() / bnorm;
      if (stats.relative_residual <= tolerance_ || solver_.info() != Eigen::Success ||
          stats.iterations >= max_iterations_ || !std::isfinite(stats.relative_residual)) {
        break;
      }
    }
    if (!(stats.relative_residual <= tolerance_)) {
      throw NumericalError(fmt::format(
          "{}: did not reach the tolerance {:.3g}: {} iterations, ||b - Ax||/||b|| = {:.3e}", name_,
          tolerance_, stats.iterations, stats.relative_residual));
    }
    x = std::move(result);
    return stats;
  }

private:
  std::string name_;
  bool symmetric_;
  double tolerance_;
  int max_iterations_;
  Solver solver_;
  SparseMatrix A_;
  bool analyzed_ = false;
  bool factorized_ = false;
};

} // namespace

namespace detail {
std::unique_ptr<LinearSolver> make_eigen_cg_solver(const LinearSolverOptions& options) {
  return std::make_unique<EigenIterativeSolver<EigenCg>>("eigen_cg", true, options);
}
std::unique_ptr<LinearSolver> make_eigen_bicgstab_solver(const LinearSolverOptions& options) {
  return std::make_unique<EigenIterativeSolver<EigenBicgstab>>("eigen_bicgstab", false, options);
}
} // namespace detail

} // namespace talus
