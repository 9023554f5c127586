// Factorize + solve time of every linear-solver backend on a 2D 5-point Poisson matrix
// (Dirichlet rows eliminated) with ~20k and ~80k unknowns: BM_LinearSolve/<backend>/<n>.
// The symbolic analysis is done once outside the timed loop, as in a Newton iteration where the
// pattern is fixed. Trilinos appears twice: <kind> (MueLu, the default) and <kind>+ifpack2.
// Counters: iterations and the true relative residual of the last solve.
#include "talus/linalg/linear_solver.hpp"

#include <benchmark/benchmark.h>

#include <random>
#include <string>
#include <vector>

namespace {

talus::SparseMatrix poisson(int m) {
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(static_cast<std::size_t>(5 * m * m));
  auto id = [m](int i, int j) { return j * m + i; };
  for (int j = 0; j < m; ++j) {
    for (int i = 0; i < m; ++i) {
      const int r = id(i, j);
      t.emplace_back(r, r, 4.0);
      if (i > 0)
        t.emplace_back(r, id(i - 1, j), -1.0);
      if (i + 1 < m)
        t.emplace_back(r, id(i + 1, j), -1.0);
      if (j > 0)
        t.emplace_back(r, id(i, j - 1), -1.0);
      if (j + 1 < m)
        t.emplace_back(r, id(i, j + 1), -1.0);
    }
  }
  talus::SparseMatrix A(m * m, m * m);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

void linear_solve(benchmark::State& state, talus::LinearSolverOptions options, int m) {
  const talus::SparseMatrix A = poisson(m);
  std::mt19937 gen(1);
  std::uniform_real_distribution<double> dist(-1.0, 1.0);
  Eigen::VectorXd xs(A.rows());
  for (Eigen::Index i = 0; i < xs.size(); ++i) {
    xs(i) = dist(gen);
  }
  const Eigen::VectorXd b = A * xs;
  auto solver = talus::make_linear_solver(options);
  solver->analyze(A);
  Eigen::VectorXd x;
  talus::LinearSolveStats stats;
  for (auto _ : state) {
    solver->factorize(A);
    stats = solver->solve(b, x);
    benchmark::DoNotOptimize(x.data());
  }
  state.counters["n"] = static_cast<double>(A.rows());
  state.counters["iterations"] = stats.iterations;
  state.counters["residual"] = stats.relative_residual;
}

int register_all() {
  for (const int m : {141, 283}) { // 19881 and 80089 unknowns
    for (const auto& name : talus::available_linear_solvers()) {
      talus::LinearSolverOptions options;
      talus::parse_linear_solver_kind(name, options.kind);
      options.tolerance = 1e-10;
      options.max_iterations = 5000;
      std::vector<std::pair<std::string, std::string>> variants = {{name, ""}};
      if (name.rfind("trilinos", 0) == 0) {
        variants = {{name, "muelu"}, {name + "+ifpack2", "ifpack2"}};
      }
      for (const auto& [label, prec] : variants) {
        options.preconditioner = prec;
        benchmark::RegisterBenchmark(
            ("BM_LinearSolve/" + label + "/" + std::to_string(m * m)).c_str(),
            [options, m](benchmark::State& state) { linear_solve(state, options, m); })
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime();
      }
    }
  }
  return 0;
}

[[maybe_unused]] const int registered = register_all();

} // namespace
