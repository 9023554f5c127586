// Sparse linear-solver backends (include/talus/linalg/linear_solver.hpp).
//
// Problems: (a) 2D 5-point Poisson on a 50x50 interior grid, Dirichlet rows eliminated (SPD,
// n = 2500, kappa_2 = cot^2(pi / (2 * 51)) ~ 1.05e3); (b) upwinded convection-diffusion on the
// same grid (nonsymmetric, diagonally dominant). b = A x* for a seeded random x*.
//
// Tolerances: for a backward-stable direct solve, ||x - x*|| / ||x*|| <~ kappa * eps * O(1) ~
// 1e-13, so 1e-10 is a safe bound. An iterative solve that stops at relative residual tol has
// ||x - x*|| / ||x*|| <= kappa_2 * ||b - Ax|| / ||b|| <= kappa_2 * tol; kappa_2 is estimated below
// by power iterations (sigma_max on A^T A, sigma_min on (A^T A)^-1 via Eigen's SparseLU), which
// can only underestimate it, hence a factor 10 of slack.
#include "talus/core/errors.hpp"
#include "talus/linalg/linear_solver.hpp"

#include <Eigen/SparseLU>
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

namespace {

using talus::LinearSolverKind;
using talus::LinearSolverOptions;
using talus::SparseMatrix;

constexpr int kGrid = 50; // 2500 unknowns
constexpr double kIterativeTolerance = 1e-10;
constexpr double kDirectErrorBound = 1e-10;

/// -Laplace on an m x m interior grid (h = 1 scaled out): 4 on the diagonal, -1 to neighbours.
/// `shift` is added to the diagonal, `scale` multiplies everything.
SparseMatrix poisson(int m, double scale = 1.0, double shift = 0.0) {
  std::vector<Eigen::Triplet<double>> t;
  auto id = [m](int i, int j) { return j * m + i; };
  for (int j = 0; j < m; ++j) {
    for (int i = 0; i < m; ++i) {
      const int r = id(i, j);
      t.emplace_back(r, r, scale * 4.0 + shift);
      if (i > 0)
        t.emplace_back(r, id(i - 1, j), -scale);
      if (i + 1 < m)
        t.emplace_back(r, id(i + 1, j), -scale);
      if (j > 0)
        t.emplace_back(r, id(i, j - 1), -scale);
      if (j + 1 < m)
        t.emplace_back(r, id(i, j + 1), -scale);
    }
  }
  SparseMatrix A(m * m, m * m);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

/// -Laplace u + (cx, cy) . grad u with first-order upwinding (cx, cy >= 0), times h^2; ch = c*h.
/// Row sums are >= 0 and the diagonal dominates: an M-matrix, nonsymmetric for c != 0.
SparseMatrix convection_diffusion(int m, double cxh, double cyh) {
  std::vector<Eigen::Triplet<double>> t;
  auto id = [m](int i, int j) { return j * m + i; };
  for (int j = 0; j < m; ++j) {
    for (int i = 0; i < m; ++i) {
      const int r = id(i, j);
      t.emplace_back(r, r, 4.0 + cxh + cyh);
      if (i > 0)
        t.emplace_back(r, id(i - 1, j), -1.0 - cxh);
      if (i + 1 < m)
        t.emplace_back(r, id(i + 1, j), -1.0);
      if (j > 0)
        t.emplace_back(r, id(i, j - 1), -1.0 - cyh);
      if (j + 1 < m)
        t.emplace_back(r, id(i, j + 1), -1.0);
    }
  }
  SparseMatrix A(m * m, m * m);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

Eigen::VectorXd random_vector(Eigen::Index n, unsigned seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> dist(-1.0, 1.0);
  Eigen::VectorXd v(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    v(i) = dist(gen);
  }
  return v;
}

/// Lower estimate of the 2-norm condition number (power iterations, see the file comment).
double condition_estimate(const SparseMatrix& A) {
  Eigen::SparseLU<SparseMatrix> lu;
  lu.compute(A);
  EXPECT_EQ(lu.info(), Eigen::Success);
  Eigen::VectorXd v = random_vector(A.cols(), 7).normalized();
  double smax2 = 0;
  for (int k = 0; k < 200; ++k) {
    Eigen::VectorXd w = A.transpose() * (A * v);
    smax2 = w.norm();
    v = w / smax2;
  }
  v = random_vector(A.cols(), 8).normalized();
  double inv_smin2 = 0;
  for (int k = 0; k < 200; ++k) {
    Eigen::VectorXd y = lu.transpose().solve(v); // A^-T v
    Eigen::VectorXd w = lu.solve(y);             // A^-1 A^-T v
    inv_smin2 = w.norm();
    v = w / inv_smin2;
  }
  return std::sqrt(smax2 * inv_smin2);
}

double relative_residual(const SparseMatrix& A, const Eigen::VectorXd& b,
                         const Eigen::VectorXd& x) {
  return (b - A * x).norm() / b.norm();
}

bool is_direct(LinearSolverKind kind) {
  return kind == LinearSolverKind::Cholmod || kind == LinearSolverKind::Umfpack ||
         kind == LinearSolverKind::Klu;
}

/// One backend configuration under test (Trilinos twice: MueLu and Ifpack2).
struct Config {
  LinearSolverOptions options;
  std::string label;
};

std::vector<Config> all_configs() {
  std::vector<Config> configs;
  for (const auto& name : talus::available_linear_solvers()) {
    LinearSolverKind kind{};
    EXPECT_TRUE(talus::parse_linear_solver_kind(name, kind)) << name;
    LinearSolverOptions options;
    options.kind = kind;
    options.tolerance = kIterativeTolerance;
    if (kind == LinearSolverKind::TrilinosCg || kind == LinearSolverKind::TrilinosGmres) {
      for (const char* prec : {"muelu", "ifpack2"}) {
        options.preconditioner = prec;
        configs.push_back({options, name + "/" + prec});
      }
    } else {
      configs.push_back({options, name});
    }
  }
  return configs;
}

bool requires_symmetric(const Config& c) {
  return talus::make_linear_solver(c.options)->requires_symmetric();
}

/// Bound on ||x - x*|| / ||x*|| for a configuration on a matrix with condition estimate kappa.
double error_bound(const Config& c, double kappa) {
  return is_direct(c.options.kind) ? kDirectErrorBound : 10.0 * kappa * c.options.tolerance;
}

/// analyze + factorize + solve, then checks x against x*, the reported residual against a
/// recomputed one and the residual against the tolerance. Returns x.
Eigen::VectorXd solve_and_check(const Config& c, const SparseMatrix& A, const Eigen::VectorXd& xs,
                                double kappa) {
  SCOPED_TRACE(c.label);
  auto solver = talus::make_linear_solver(c.options);
  const Eigen::VectorXd b = A * xs;
  Eigen::VectorXd x;
  solver->analyze(A);
  solver->factorize(A);
  const auto stats = solver->solve(b, x);
  EXPECT_EQ(x.size(), xs.size());
  const double res = relative_residual(A, b, x);
  EXPECT_NEAR(stats.relative_residual, res, 1e-3 * res + 1e-300);
  EXPECT_GE(stats.iterations, 1);
  if (is_direct(c.options.kind)) {
    EXPECT_EQ(stats.iterations, 1);
    EXPECT_LT(res, 1e-13);
  } else {
    EXPECT_LE(res, c.options.tolerance);
  }
  EXPECT_LE((x - xs).norm() / xs.norm(), error_bound(c, kappa));
  return x;
}

struct Problems {
  SparseMatrix spd = poisson(kGrid);
  SparseMatrix general = convection_diffusion(kGrid, 0.5, 0.25);
  double kappa_spd = condition_estimate(spd);
  double kappa_general = condition_estimate(general);
  Eigen::VectorXd xs = random_vector(kGrid * kGrid, 42);
};

const Problems& problems() {
  static const Problems p;
  return p;
}

TEST(LinearSolverNames, RoundTripAndAvailability) {
  const std::vector<std::pair<LinearSolverKind, std::string>> all = {
      {LinearSolverKind::Cholmod, "cholmod"},
      {LinearSolverKind::Umfpack, "umfpack"},
      {LinearSolverKind::Klu, "klu"},
      {LinearSolverKind::EigenCg, "eigen_cg"},
      {LinearSolverKind::EigenBicgstab, "eigen_bicgstab"},
      {LinearSolverKind::TrilinosCg, "trilinos_cg"},
      {LinearSolverKind::TrilinosGmres, "trilinos_gmres"}};
  for (const auto& [kind, name] : all) {
    EXPECT_EQ(talus::to_string(kind), name);
    LinearSolverKind parsed = LinearSolverKind::Cholmod;
    ASSERT_TRUE(talus::parse_linear_solver_kind(name, parsed)) << name;
    EXPECT_EQ(parsed, kind);
  }
  LinearSolverKind kind = LinearSolverKind::Klu;
  EXPECT_FALSE(talus::parse_linear_solver_kind("superlu", kind));
  EXPECT_FALSE(talus::parse_linear_solver_kind("", kind));
  EXPECT_FALSE(talus::parse_linear_solver_kind("CHOLMOD", kind));
  EXPECT_EQ(kind, LinearSolverKind::Klu); // untouched on failure

  const auto available = talus::available_linear_solvers();
  for (const char* always : {"cholmod", "umfpack", "klu", "eigen_cg", "eigen_bicgstab"}) {
    EXPECT_NE(std::find(available.begin(), available.end(), always), available.end()) << always;
  }
  for (const auto& [k, name] : all) {
    LinearSolverOptions options;
    options.kind = k;
    const bool built = std::find(available.begin(), available.end(), name) != available.end();
    if (built) {
      auto solver = talus::make_linear_solver(options);
      ASSERT_NE(solver, nullptr);
      EXPECT_EQ(solver->name(), name);
    } else {
      EXPECT_THROW(talus::make_linear_solver(options), std::invalid_argument) << name;
    }
  }
#ifdef TALUS_HAVE_TRILINOS
  EXPECT_EQ(available.size(), 7u);
  LinearSolverOptions bad;
  bad.kind = LinearSolverKind::TrilinosCg;
  bad.preconditioner = "jacobi";
  EXPECT_THROW(talus::make_linear_solver(bad), std::invalid_argument);
#else
  EXPECT_EQ(available.size(), 5u);
#endif
}

// The automatic backend: direct below the measured 3D crossover and in 2D at any size (fill
// n log n), CG (symmetric) or GMRES (nonsymmetric) with MueLu above it.
TEST(LinearSolverNames, AutomaticChoiceFollowsTheMeasuredCrossover) {
  using talus::automatic_linear_solver;
  using talus::kIterativeUnknowns3d;
  EXPECT_EQ(automatic_linear_solver(true, 2, 10 * kIterativeUnknowns3d), LinearSolverKind::Cholmod);
  EXPECT_EQ(automatic_linear_solver(false, 2, 10 * kIterativeUnknowns3d),
            LinearSolverKind::Umfpack);
  EXPECT_EQ(automatic_linear_solver(true, 3, kIterativeUnknowns3d - 1), LinearSolverKind::Cholmod);
  EXPECT_EQ(automatic_linear_solver(false, 3, kIterativeUnknowns3d - 1), LinearSolverKind::Umfpack);
#ifdef TALUS_HAVE_TRILINOS
  EXPECT_EQ(automatic_linear_solver(true, 3, kIterativeUnknowns3d), LinearSolverKind::TrilinosCg);
  EXPECT_EQ(automatic_linear_solver(false, 3, kIterativeUnknowns3d),
            LinearSolverKind::TrilinosGmres);
#else
  EXPECT_EQ(automatic_linear_solver(true, 3, kIterativeUnknowns3d), LinearSolverKind::Cholmod);
  EXPECT_EQ(automatic_linear_solver(false, 3, kIterativeUnknowns3d), LinearSolverKind::Umfpack);
#endif
}

TEST(LinearSolverBackends, ConditionEstimatesAreSane) {
  const auto& p = problems();
  // Poisson: kappa_2 = cot^2(pi / (2 (m + 1))) exactly.
  const double exact = std::pow(1.0 / std::tan(std::numbers::pi / (2.0 * (kGrid + 1))), 2);
  EXPECT_NEAR(p.kappa_spd, exact, 0.01 * exact);
  EXPECT_GT(p.kappa_general, 10.0);
  EXPECT_LT(p.kappa_general, 1e5);
}

TEST(LinearSolverBackends, SpdPoisson) {
  const auto& p = problems();
  for (const auto& c : all_configs()) {
    solve_and_check(c, p.spd, p.xs, p.kappa_spd);
  }
}

TEST(LinearSolverBackends, NonsymmetricConvectionDiffusion) {
  const auto& p = problems();
  int tested = 0;
  for (const auto& c : all_configs()) {
    if (!requires_symmetric(c)) {
      solve_and_check(c, p.general, p.xs, p.kappa_general);
      ++tested;
    }
  }
  EXPECT_GE(tested, 3);
}

TEST(LinearSolverBackends, AnalyzeOnceFactorizeTwice) {
  const auto& p = problems();
  // Same patterns, different values (the diagonal shift keeps A2 SPD / an M-matrix).
  const SparseMatrix spd2 = poisson(kGrid, 2.5, 0.3);
  const SparseMatrix general2 = convection_diffusion(kGrid, 2.0, 0.1);
  const double kappa_spd2 = condition_estimate(spd2);
  const double kappa_general2 = condition_estimate(general2);
  const Eigen::VectorXd xs2 = random_vector(kGrid * kGrid, 43);
  for (const auto& c : all_configs()) {
    SCOPED_TRACE(c.label);
    const bool spd = requires_symmetric(c);
    const SparseMatrix& A1 = spd ? p.spd : p.general;
    const SparseMatrix& A2 = spd ? spd2 : general2;
    const double k1 = spd ? p.kappa_spd : p.kappa_general;
    const double k2 = spd ? kappa_spd2 : kappa_general2;
    auto solver = talus::make_linear_solver(c.options);
    solver->analyze(A1);
    for (int round = 0; round < 2; ++round) { // A1, A2, A1, A2: refactorisations both ways
      for (int which = 0; which < 2; ++which) {
        const SparseMatrix& A = which == 0 ? A1 : A2;
        const Eigen::VectorXd& xs = which == 0 ? p.xs : xs2;
        const Eigen::VectorXd b = A * xs;
        Eigen::VectorXd x;
        solver->factorize(A);
        const auto stats = solver->solve(b, x);
        EXPECT_NEAR(stats.relative_residual, relative_residual(A, b, x),
                    1e-3 * stats.relative_residual + 1e-300);
        EXPECT_LE((x - xs).norm() / xs.norm(), error_bound(c, which == 0 ? k1 : k2))
            << "round " << round << " matrix " << which;
      }
    }
    // Two right-hand sides with one factorisation.
    const Eigen::VectorXd b = A2 * p.xs;
    Eigen::VectorXd x;
    solver->solve(b, x);
    EXPECT_LE((x - p.xs).norm() / p.xs.norm(), error_bound(c, k2));
  }
}

TEST(LinearSolverBackends, AllBackendsAgree) {
  const auto& p = problems();
  for (const bool spd : {true, false}) {
    const SparseMatrix& A = spd ? p.spd : p.general;
    const double kappa = spd ? p.kappa_spd : p.kappa_general;
    std::vector<std::pair<Config, Eigen::VectorXd>> solutions;
    for (const auto& c : all_configs()) {
      if (spd || !requires_symmetric(c)) {
        solutions.emplace_back(c, solve_and_check(c, A, p.xs, kappa));
      }
    }
    ASSERT_GE(solutions.size(), spd ? 5u : 3u);
    for (std::size_t i = 0; i < solutions.size(); ++i) {
      for (std::size_t j = i + 1; j < solutions.size(); ++j) {
        const auto& [ci, xi] = solutions[i];
        const auto& [cj, xj] = solutions[j];
        EXPECT_LE((xi - xj).norm() / p.xs.norm(), error_bound(ci, kappa) + error_bound(cj, kappa))
            << ci.label << " vs " << cj.label << (spd ? " (Poisson)" : " (convection-diffusion)");
      }
    }
  }
}

TEST(LinearSolverBackends, DirectSolversRejectSingularMatrices) {
  const auto& p = problems();
  const int k = 1234;
  // Zero row k (stored entries kept, values zero): singular for LU.
  SparseMatrix zero_row = p.general;
  // Zero row and column k: symmetric positive semidefinite, singular for Cholesky.
  SparseMatrix zero_row_col = p.spd;
  for (int col = 0; col < zero_row.outerSize(); ++col) {
    for (SparseMatrix::InnerIterator it(zero_row, col); it; ++it) {
      if (it.row() == k)
        it.valueRef() = 0.0;
    }
    for (SparseMatrix::InnerIterator it(zero_row_col, col); it; ++it) {
      if (it.row() == k || it.col() == k)
        it.valueRef() = 0.0;
    }
  }
  // The same with the zeros removed from the pattern (structurally singular).
  SparseMatrix pruned = zero_row;
  pruned.prune(0.0, 0.0);
  ASSERT_LT(pruned.nonZeros(), zero_row.nonZeros());
  for (const auto kind :
       {LinearSolverKind::Cholmod, LinearSolverKind::Umfpack, LinearSolverKind::Klu}) {
    SCOPED_TRACE(talus::to_string(kind));
    LinearSolverOptions options;
    options.kind = kind;
    auto solver = talus::make_linear_solver(options);
    std::vector<const SparseMatrix*> singular = {&zero_row_col};
    if (!solver->requires_symmetric()) {
      singular.push_back(&zero_row);
      singular.push_back(&pruned);
    }
    for (const SparseMatrix* A : singular) {
      solver->analyze(*A);
      // The pivot is named in the matrix's own numbering: column k when row and column k are
      // zero (an unknown with no stiffness); some column when only a row is.
      try {
        solver->factorize(*A);
        ADD_FAILURE() << "expected SingularPivot";
      } catch (const talus::SingularPivot& e) {
        if (A == &zero_row_col) {
          EXPECT_EQ(e.unknown(), k) << e.what();
        }
        EXPECT_GE(e.unknown(), 0) << e.what();
        EXPECT_LT(e.unknown(), A->rows()) << e.what();
        EXPECT_NE(std::string(e.what()).find(fmt::format("column {} of", e.unknown())),
                  std::string::npos)
            << e.what();
      }
      Eigen::VectorXd x;
      EXPECT_THROW(solver->solve(Eigen::VectorXd::Ones(A->rows()), x), std::logic_error);
    }
    // The solver recovers: a regular matrix with the same pattern factorises again.
    solver->analyze(zero_row_col);
    EXPECT_THROW(solver->factorize(zero_row_col), talus::NumericalError);
    solver->factorize(p.spd);
    Eigen::VectorXd x;
    solver->solve(p.spd * p.xs, x);
    EXPECT_LE((x - p.xs).norm() / p.xs.norm(), kDirectErrorBound);
  }
}

TEST(LinearSolverBackends, CholmodRejectsIndefiniteMatrix) {
  // Poisson eigenvalues lie in (0, 8); shifting by -1 makes the matrix symmetric indefinite.
  // Two sizes: CHOLMOD factorises the small one simplicially (LDL', which does not break down on
  // an indefinite matrix by itself) and the large one supernodally (LL').
  LinearSolverOptions options;
  options.kind = LinearSolverKind::Cholmod;
  for (const int m : {kGrid, 160}) {
    SCOPED_TRACE(m);
    const SparseMatrix A = poisson(m, 1.0, -1.0);
    auto solver = talus::make_linear_solver(options);
    solver->analyze(A);
    try {
      solver->factorize(A);
      ADD_FAILURE() << "expected NumericalError";
    } catch (const talus::NumericalError& e) {
      EXPECT_NE(std::string(e.what()).find("cholmod"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("positive definite"), std::string::npos) << e.what();
    }
    // The same solver object still works on an SPD matrix afterwards.
    const SparseMatrix spd = poisson(m);
    solver->factorize(spd);
    const Eigen::VectorXd xs = random_vector(m * m, 5);
    Eigen::VectorXd x;
    solver->solve(spd * xs, x);
    EXPECT_LE((x - xs).norm() / xs.norm(), kDirectErrorBound);
  }
  // UMFPACK and KLU do solve the indefinite (regular) matrix.
  const SparseMatrix A = poisson(kGrid, 1.0, -1.0);
  const double kappa = condition_estimate(A);
  for (const auto kind : {LinearSolverKind::Umfpack, LinearSolverKind::Klu}) {
    options.kind = kind;
    auto lu = talus::make_linear_solver(options);
    lu->analyze(A);
    lu->factorize(A);
    const Eigen::VectorXd xs = problems().xs;
    Eigen::VectorXd x;
    lu->solve(A * xs, x);
    EXPECT_LE((x - xs).norm() / xs.norm(), 10.0 * kappa * 1e-14) << talus::to_string(kind);
  }
}

TEST(LinearSolverBackends, IterativeSolversReportMissedTolerance) {
  const auto& p = problems();
  const Eigen::VectorXd b = p.spd * p.xs;
  for (auto c : all_configs()) {
    if (is_direct(c.options.kind))
      continue;
    SCOPED_TRACE(c.label);
    c.options.tolerance = 1e-14;
    c.options.max_iterations = 2;
    auto solver = talus::make_linear_solver(c.options);
    solver->analyze(p.spd);
    solver->factorize(p.spd);
    Eigen::VectorXd x;
    try {
      solver->solve(b, x);
      FAIL() << "expected NumericalError";
    } catch (const talus::NumericalError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(solver->name()), std::string::npos) << what;
      EXPECT_NE(what.find("iterations"), std::string::npos) << what;
    }
  }
}

TEST(LinearSolverBackends, ZeroRightHandSideAndMisuse) {
  const auto& p = problems();
  for (const auto& c : all_configs()) {
    SCOPED_TRACE(c.label);
    auto solver = talus::make_linear_solver(c.options);
    Eigen::VectorXd x;
    EXPECT_THROW(solver->factorize(p.spd), std::logic_error); // before analyze
    solver->analyze(p.spd);
    EXPECT_THROW(solver->solve(Eigen::VectorXd::Ones(p.spd.rows()), x), std::logic_error);
    EXPECT_THROW(solver->factorize(poisson(kGrid - 1)), std::invalid_argument); // other pattern
    solver->factorize(p.spd);
    const auto stats = solver->solve(Eigen::VectorXd::Zero(p.spd.rows()), x);
    EXPECT_EQ(x.size(), p.spd.rows());
    EXPECT_EQ(x.norm(), 0.0);
    EXPECT_EQ(stats.relative_residual, 0.0);
    EXPECT_THROW(solver->solve(Eigen::VectorXd::Ones(3), x), std::invalid_argument);
  }
}

} // namespace
