// The KINSOL-driven Newton solver on a nonlinear problem with a known discrete solution:
// -u'' + u^3 = f on (0, 1), u(0) = u(1) = 0, second-order differences, f chosen so that
// u_i = a sin(pi x_i) solves the discrete equations exactly.
#include "talus/core/errors.hpp"
#include "talus/solver/newton.hpp"

#include <Eigen/SparseLU>
#include <cmath>
#include <gtest/gtest.h>
#include <numbers>

using namespace talus;

namespace {

// A test double for the linear-solver backends: Eigen's sparse LU.
class SparseLuSolver final : public LinearSolver {
public:
  std::string name() const override { return "eigen-sparselu (test)"; }
  bool requires_symmetric() const override { return false; }
  void analyze(const SparseMatrix& A) override { lu_.analyzePattern(A); }
  void factorize(const SparseMatrix& A) override {
    lu_.factorize(A);
    if (lu_.info() != Eigen::Success)
      throw NumericalError("singular");
  }
  LinearSolveStats solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) override {
    x = lu_.solve(b);
    return {1, 0.0};
  }

private:
  Eigen::SparseLU<SparseMatrix> lu_;
};

class CubicReactionDiffusion final : public NonlinearSystem {
public:
  CubicReactionDiffusion(int n, double amplitude) : n_(n), h_(1.0 / (n + 1)), f_(n), exact_(n) {
    for (int i = 0; i < n; ++i)
      exact_[i] = amplitude * std::sin(std::numbers::pi * (i + 1) * h_);
    for (int i = 0; i < n; ++i)
      f_[i] = stencil(exact_, i) + std::pow(exact_[i], 3);
  }
  Index size() const override { return n_; }
  bool residual(const Eigen::VectorXd& u, Eigen::VectorXd& r) override {
    if (admissible_limit_ > 0 && u.cwiseAbs().maxCoeff() > admissible_limit_)
      return false;
    r.resize(n_);
    for (int i = 0; i < n_; ++i)
      r[i] = stencil(u, i) + std::pow(u[i], 3) - f_[i];
    return true;
  }
  const SparseMatrix& jacobian(const Eigen::VectorXd& u) override {
    std::vector<Eigen::Triplet<double>> t;
    for (int i = 0; i < n_; ++i) {
      t.emplace_back(i, i, 2.0 / (h_ * h_) + 3.0 * u[i] * u[i]);
      if (i > 0)
        t.emplace_back(i, i - 1, -1.0 / (h_ * h_));
      if (i + 1 < n_)
        t.emplace_back(i, i + 1, -1.0 / (h_ * h_));
    }
    J_.resize(n_, n_);
    J_.setFromTriplets(t.begin(), t.end());
    J_.makeCompressed();
    return J_;
  }
  // The pattern never changes: one analysis serves every solve.
  bool pattern_changed() const override { return !analysed_; }
  void pattern_analysed() override { analysed_ = true; }
  const Eigen::VectorXd& exact() const { return exact_; }
  double force_scale() const { return f_.lpNorm<Eigen::Infinity>(); }
  void reject_states_above(double limit) { admissible_limit_ = limit; }

private:
  double stencil(const Eigen::VectorXd& u, int i) const {
    const double left = i > 0 ? u[i - 1] : 0.0;
    const double right = i + 1 < n_ ? u[i + 1] : 0.0;
    return (-left + 2.0 * u[i] - right) / (h_ * h_);
  }
  int n_;
  double h_;
  bool analysed_ = false;
  Eigen::VectorXd f_, exact_;
  SparseMatrix J_;
  double admissible_limit_ = 0;
};

} // namespace

TEST(Newton, ConvergesQuadraticallyToTheDiscreteSolution) {
  CubicReactionDiffusion problem(200, 20.0); // strongly nonlinear: u^3 ~ 8000 vs u'' ~ 200
  SparseLuSolver lu;
  NewtonOptions options;
  options.residual_tolerance = 1e-12;
  options.residual_scale = problem.force_scale();
  Eigen::VectorXd u = Eigen::VectorXd::Zero(200);
  const NewtonReport report = solve_newton(problem, lu, u, options);
  ASSERT_TRUE(report.converged) << report.message;
  EXPECT_LT((u - problem.exact()).lpNorm<Eigen::Infinity>(), 1e-9 * 20.0);
  EXPECT_EQ(report.factorizations, report.iterations);
  EXPECT_EQ(report.symbolic_analyses, 1); // the pattern never changes
  // Quadratic convergence: once the residual is small, each iterate squares it
  // (log r_{k+1} / log r_k ~ 2). Require >= 1.8 on every step from below 1e-2 whose result is
  // above the round-off floor, cond(J) * eps ~ 4 / (pi h)^2 * 2.2e-16 ~ 4e-12 here.
  const auto& r = report.residual_history;
  ASSERT_GE(r.size(), 3u);
  int quadratic_steps = 0;
  for (std::size_t k = 0; k + 1 < r.size(); ++k)
    if (r[k] < 1e-2 && r[k + 1] > 1e-11) {
      EXPECT_GE(std::log(r[k + 1]) / std::log(r[k]), 1.8) << "step " << k;
      ++quadratic_steps;
    }
  EXPECT_GE(quadratic_steps, 1);
}

TEST(Newton, BacktracksFromInadmissibleStates) {
  CubicReactionDiffusion problem(100, 1.0);
  problem.reject_states_above(1.5); // the residual refuses |u| > 1.5, e.g. a failed material
  SparseLuSolver lu;
  NewtonOptions options;
  options.residual_scale = problem.force_scale();
  // Start far on the other side so the first full Newton step would overshoot.
  Eigen::VectorXd u = Eigen::VectorXd::Constant(100, -1.4);
  const NewtonReport report = solve_newton(problem, lu, u, options);
  ASSERT_TRUE(report.converged) << report.message;
  EXPECT_LT((u - problem.exact()).lpNorm<Eigen::Infinity>(), 1e-6);
}

TEST(Newton, ReportsNonConvergence) {
  CubicReactionDiffusion problem(100, 20.0);
  SparseLuSolver lu;
  NewtonOptions options;
  options.residual_scale = problem.force_scale();
  options.max_iterations = 2;
  options.extension = 1; // exactly two iterations
  Eigen::VectorXd u = Eigen::VectorXd::Zero(100);
  const Eigen::VectorXd start = u;
  const NewtonReport report = solve_newton(problem, lu, u, options);
  EXPECT_FALSE(report.converged);
  EXPECT_FALSE(report.message.empty());
  EXPECT_EQ(u, start); // the caller's state is untouched when Newton fails
}

// Past max_iterations an attempt goes on while its residual keeps falling: the problem above
// converges in 5 iterations (quadratically after the first), so two iterations plus the
// extension reach it; without the extension they did not (ReportsNonConvergence).
TEST(Newton, GoesOnPastTheBudgetWhileItProgresses) {
  CubicReactionDiffusion problem(100, 20.0);
  SparseLuSolver lu;
  NewtonOptions options;
  options.residual_scale = problem.force_scale();
  options.max_iterations = 2;
  Eigen::VectorXd u = Eigen::VectorXd::Zero(100);
  const NewtonReport report = solve_newton(problem, lu, u, options);
  EXPECT_TRUE(report.converged) << report.message;
  EXPECT_GT(report.iterations, 2);
  EXPECT_LE(report.iterations, 8);
}

namespace {
// r(x) = x^2 + 1 has no real root: Newton's iterates wander without the residual falling.
class NoRoot final : public NonlinearSystem {
public:
  Index size() const override { return 1; }
  bool residual(const Eigen::VectorXd& u, Eigen::VectorXd& r) override {
    r.resize(1);
    r[0] = u[0] * u[0] + 1.0;
    return true;
  }
  const SparseMatrix& jacobian(const Eigen::VectorXd& u) override {
    J_.resize(1, 1);
    J_.setZero();
    J_.insert(0, 0) = u[0] != 0.0 ? 2.0 * u[0] : 1.0;
    J_.makeCompressed();
    return J_;
  }
  bool pattern_changed() const override { return !analysed_; }
  void pattern_analysed() override { analysed_ = true; }

private:
  SparseMatrix J_;
  bool analysed_ = false;
};
} // namespace

// ... and stops once it stands still: the residual of r = x^2 + 1 never falls below 1, so the
// attempt ends at the first window check past max_iterations, far short of extension times it,
// and says why.
TEST(Newton, StopsPastTheBudgetWhenItStagnates) {
  NoRoot problem;
  SparseLuSolver lu;
  NewtonOptions options;
  options.line_search = false;
  options.max_iterations = 12;
  options.extension = 10;
  Eigen::VectorXd u = Eigen::VectorXd::Constant(1, 0.5);
  const NewtonReport report = solve_newton(problem, lu, u, options);
  EXPECT_FALSE(report.converged);
  EXPECT_LE(report.iterations, 13);
  EXPECT_NE(report.message.find("no progress after"), std::string::npos) << report.message;
}
