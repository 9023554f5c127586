// The cost of the frames' post-processing against one explicit step, on the reference talk's
// colliding discs (cases/colliding_discs.yaml) at the case's cell size h = 0.025 (1624 points)
// and refined to h / 4 (26k points):
//   BM_ExplicitStep/<cells>          one explicit MUSL step (the solver's own cost)
//   BM_RecoveryAndVoxels/<cells>     grid-node + smoothed stress and the deformed voxels
//   BM_FrameWrite/<cells>/<post>     writing one frame to run.h5 + run.xmf, without (0) or with
//                                    (1) the stress recovery and voxel datasets
// The target: recovery plus voxel output at most 20 % of one explicit step per frame,
// i.e. BM_RecoveryAndVoxels + (BM_FrameWrite/1 - BM_FrameWrite/0) against BM_ExplicitStep.
// Run single-threaded for a stable comparison: OMP_NUM_THREADS=1 build/bench/talus_bench
// --benchmark_filter='Explicit|Recovery|FrameWrite'.
#include "talus/io/case_reader.hpp"
#include "talus/io/results.hpp"
#include "talus/post/stress_recovery.hpp"
#include "talus/post/voxels.hpp"
#include "talus/scene/scene.hpp"
#include "talus/solver/explicit_solver.hpp"

#include <benchmark/benchmark.h>
#include <filesystem>
#include <fmt/format.h>
#include <unistd.h>

namespace {

using namespace talus;

/// The colliding discs with `cells` cells along the unit square, advanced a few steps so that
/// the stresses are not zero.
Scene<2> discs(int cells) {
  const CaseSpec spec =
      read_case_file(std::string(TALUS_SOURCE_DIR) + "/cases/colliding_discs.yaml",
                     {fmt::format("grid.cell_size={:.17g}", 1.0 / cells)});
  Scene<2> scene = build_scene<2>(spec);
  auto solver = make_explicit_solver(scene);
  for (int k = 0; k < 5; ++k)
    solver->step(solver->stable_dt(0.5));
  return scene;
}

void BM_ExplicitStep(benchmark::State& state) {
  Scene<2> scene = discs(static_cast<int>(state.range(0)));
  auto solver = make_explicit_solver(scene);
  const double dt = solver->stable_dt(0.5);
  for (auto _ : state)
    solver->step(dt);
  state.counters["particles"] = static_cast<double>(scene.particles.size());
}

void BM_RecoveryAndVoxels(benchmark::State& state) {
  const Scene<2> scene = discs(static_cast<int>(state.range(0)));
  // As in a run: one recovery object and one voxel set, reused frame after frame.
  StressRecovery<2> recovery(scene.grid, scene.spec.solver.shape);
  Voxels<2> voxels;
  for (auto _ : state) {
    const RecoveredStress<2>& r = recovery.recover(scene.particles);
    update_voxels(scene.particles, scene.grid.origin(), scene.grid.cell_size(), voxels);
    benchmark::DoNotOptimize(r.smoothed_stress.data());
    benchmark::DoNotOptimize(voxels.corners.data());
  }
  state.counters["particles"] = static_cast<double>(scene.particles.size());
}

void BM_FrameWrite(benchmark::State& state) {
  const Scene<2> scene = discs(static_cast<int>(state.range(0)));
  const bool post = state.range(1) != 0;
  StressRecovery<2> recovery(scene.grid, scene.spec.solver.shape);
  const RecoveredStress<2>& r = recovery.recover(scene.particles);
  Voxels<2> v;
  update_voxels(scene.particles, scene.grid.origin(), scene.grid.cell_size(), v);
  const auto dir =
      std::filesystem::temp_directory_path() / fmt::format("talus_bench_frames_{}", ::getpid());
  {
    RunMetadata meta;
    meta.case_name = "bench";
    meta.cell_size = scene.grid.cell_size();
    ResultsWriter writer(dir, meta);
    Index step = 0;
    for (auto _ : state)
      writer.write_frame(step++, 0.0, scene.particles, scene.spec.output.fields,
                         post ? FramePost<2>{&r, &v} : FramePost<2>{});
  }
  std::filesystem::remove_all(dir);
}

// 50 steps: the discs are still apart (the whole case is ~570 steps at 40 cells).
BENCHMARK(BM_ExplicitStep)->Arg(40)->Arg(160)->Iterations(50)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RecoveryAndVoxels)->Arg(40)->Arg(160)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FrameWrite)
    ->Args({40, 0})
    ->Args({40, 1})
    ->Args({160, 0})
    ->Args({160, 1})
    ->Iterations(40) // run.xmf lists every frame so far: 40 frames, a typical run's count
    ->Unit(benchmark::kMillisecond);

} // namespace
