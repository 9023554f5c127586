// The bare linear solve of a real Newton system: a tangent written by `talus run
// --dump-tangent FILE` (Matrix Market), named by the environment variable TALUS_TANGENT, solved by
// the backend TALUS_TANGENT_SOLVER (default cholmod). Two benchmarks:
//   BM_DumpedTangent/<solver>/factor_solve  numeric factorisation + one solve, the analysis done
//                                           once outside the loop (a Newton iteration's share)
//   BM_DumpedTangent/<solver>/analyze       the symbolic analysis alone
// docs/performance.md compares the time per Newton iteration of the run that wrote the file
// with factor_solve. Without TALUS_TANGENT nothing is registered.
#include "talus/linalg/linear_solver.hpp"

#include <benchmark/benchmark.h>
#include <unsupported/Eigen/SparseExtra>

#include <cstdlib>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>

namespace {

struct DumpedSystem {
  talus::SparseMatrix A;
  Eigen::VectorXd b;
  talus::LinearSolverOptions options;
};

/// The dumped matrix and a right-hand side with a known solution, read once.
const DumpedSystem& dumped_system() {
  static const std::unique_ptr<DumpedSystem> system = [] {
    auto s = std::make_unique<DumpedSystem>();
    const char* file = std::getenv("TALUS_TANGENT");
    if (file == nullptr || !Eigen::loadMarket(s->A, file))
      throw std::runtime_error("cannot read the Matrix Market file in TALUS_TANGENT");
    s->A.makeCompressed();
    std::mt19937 gen(1);
    std::uniform_real_distribution<double> dist(-1.0, 1.0);
    Eigen::VectorXd x(s->A.rows());
    for (Eigen::Index i = 0; i < x.size(); ++i)
      x(i) = dist(gen);
    s->b = s->A * x;
    const char* solver = std::getenv("TALUS_TANGENT_SOLVER");
    if (!talus::parse_linear_solver_kind(solver ? solver : "cholmod", s->options.kind))
      throw std::runtime_error("unknown TALUS_TANGENT_SOLVER");
    return s;
  }();
  return *system;
}

void factor_solve(benchmark::State& state) {
  const DumpedSystem& s = dumped_system();
  auto solver = talus::make_linear_solver(s.options);
  solver->analyze(s.A);
  Eigen::VectorXd x;
  talus::LinearSolveStats stats;
  for (auto _ : state) {
    solver->factorize(s.A);
    stats = solver->solve(s.b, x);
    benchmark::DoNotOptimize(x.data());
  }
  state.counters["n"] = static_cast<double>(s.A.rows());
  state.counters["nonzeros"] = static_cast<double>(s.A.nonZeros());
  state.counters["residual"] = stats.relative_residual;
}

void analyze(benchmark::State& state) {
  const DumpedSystem& s = dumped_system();
  auto solver = talus::make_linear_solver(s.options);
  for (auto _ : state)
    solver->analyze(s.A);
}

int register_dumped() {
  if (std::getenv("TALUS_TANGENT") == nullptr)
    return 0;
  const char* solver = std::getenv("TALUS_TANGENT_SOLVER");
  const std::string label = std::string("BM_DumpedTangent/") + (solver ? solver : "cholmod");
  benchmark::RegisterBenchmark((label + "/factor_solve").c_str(), factor_solve)
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime();
  benchmark::RegisterBenchmark((label + "/analyze").c_str(), analyze)
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime();
  return 0;
}

[[maybe_unused]] const int registered = register_dumped();

} // namespace
