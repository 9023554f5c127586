// The implicit solver's assembly on the large-deflection cantilever (cases/cantilever_large.yaml:
// 1600 points, GIMP, ghost penalty), at the first load step's state:
//   BM_AssemblyTangentStructure  a tangent pass that builds the sparsity structure (the first
//                                Newton iteration of every load step)
//   BM_AssemblyTangent           a tangent pass into the built structure (every later
//                                iteration)
//   BM_AssemblyResidual          the residual (material update cached, as in Newton)
//   BM_AssemblyShares/<shares>   material update, residual and tangent (structure built) of every
//                                share, the points split into <shares> equal ranges: the
//                                distributed path's work on one process
// The first three do not time the material update (assemble_share caches it for an unchanged
// increment); the last alternates between two increments so that every pass updates. Each
// tangent pass includes the copy assemble_share makes into the caller's matrix (Newton's own
// path, jacobian(), uses the assembler's matrix in place).
// Run: build/bench/talus_bench --benchmark_filter=Assembly
#include "../src/solver/implicit_share_assembly.hpp"
#include "talus/io/case_reader.hpp"
#include "talus/scene/scene.hpp"
#include "talus/solver/implicit_solver.hpp"

#include <benchmark/benchmark.h>

#include <memory>
#include <vector>

namespace {

using namespace talus;

struct Beam {
  Beam()
      : scene(build_scene<2>(
            read_case_file(std::string(TALUS_SOURCE_DIR) + "/cases/cantilever_large.yaml"))),
        owned(make_implicit_solver(scene)), solver(&share_assembly(*owned)) {
    solver->prepare(0.02, 0.02, 0.02); // the first of the case's 50 load steps
    du = Eigen::VectorXd::Zero(solver->unknowns());
  }
  Scene<2> scene;
  std::unique_ptr<ImplicitSolver> owned;
  ImplicitShareAssembly* solver; ///< owned's assembly by shares
  Eigen::VectorXd du;
};

/// One share per range of points, with its DOF map, increment and tangent.
struct Shares {
  Shares(ImplicitShareAssembly& solver, Index points, int count, const Eigen::VectorXd& du)
      : shares(split_particles(points, count)) {
    const std::vector<int> owners = solver.node_owners(shares);
    const Eigen::VectorXd other = du.array() + 1e-6; // a second increment, 1e-5 of a cell
    for (const ParticleShare& share : shares) {
      maps.push_back(solver.dof_map(share, owners));
      increments.push_back(maps.back().restrict_to_overlap(du));
      other_increments.push_back(maps.back().restrict_to_overlap(other));
    }
    tangents.resize(shares.size());
  }
  std::vector<ParticleShare> shares;
  std::vector<DofMap> maps;
  std::vector<Eigen::VectorXd> increments, other_increments;
  std::vector<SparseMatrix> tangents;
};

void tangent_pass(benchmark::State& state, bool new_structure) {
  Beam beam;
  Shares one(*beam.solver, beam.scene.particles.size(), 1, beam.du);
  SparseMatrix& tangent = one.tangents[0];
  Eigen::VectorXd r;
  for (auto _ : state) {
    if (new_structure) { // a new step: the structure is built again at its first tangent
      state.PauseTiming();
      beam.solver->prepare(0.02, 0.02, 0.02);
      beam.solver->assemble_share(one.shares[0], one.maps[0], one.increments[0], &r, nullptr);
      state.ResumeTiming();
    }
    beam.solver->assemble_share(one.shares[0], one.maps[0], one.increments[0], nullptr, &tangent);
    benchmark::DoNotOptimize(tangent.valuePtr());
  }
  state.counters["unknowns"] = static_cast<double>(beam.solver->unknowns());
}

void BM_AssemblyTangentStructure(benchmark::State& state) {
  tangent_pass(state, true);
}
void BM_AssemblyTangent(benchmark::State& state) {
  tangent_pass(state, false);
}

void BM_AssemblyResidual(benchmark::State& state) {
  Beam beam;
  Shares one(*beam.solver, beam.scene.particles.size(), 1, beam.du);
  Eigen::VectorXd r;
  for (auto _ : state) {
    beam.solver->assemble_share(one.shares[0], one.maps[0], one.increments[0], &r, nullptr);
    benchmark::DoNotOptimize(r.data());
  }
}

void BM_AssemblyShares(benchmark::State& state) {
  Beam beam;
  Shares split(*beam.solver, beam.scene.particles.size(), static_cast<int>(state.range(0)),
               beam.du);
  Eigen::VectorXd r;
  for (std::size_t s = 0; s < split.shares.size(); ++s) // build every share's structure
    beam.solver->assemble_share(split.shares[s], split.maps[s], split.increments[s], nullptr,
                                &split.tangents[s]);
  bool other = true;
  for (auto _ : state) {
    for (std::size_t s = 0; s < split.shares.size(); ++s) {
      const auto& du = other ? split.other_increments[s] : split.increments[s];
      beam.solver->assemble_share(split.shares[s], split.maps[s], du, &r, &split.tangents[s]);
      benchmark::DoNotOptimize(split.tangents[s].valuePtr());
    }
    other = !other;
  }
}

} // namespace

BENCHMARK(BM_AssemblyTangentStructure)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_AssemblyTangent)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_AssemblyResidual)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_AssemblyShares)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);
