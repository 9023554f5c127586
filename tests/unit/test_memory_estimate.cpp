// The memory estimate (core/memory_estimate.hpp) against the heap a small scene really takes:
// glibc's mallinfo2 before and after building the scene, making the solver and taking one step
// (which builds the particle-grid map and, implicitly, the matrix and its factor).
#include "talus/io/case_reader.hpp"
#include "talus/scene/memory_estimate.hpp"
#include "talus/scene/scene.hpp"
#include "talus/solver/explicit_solver.hpp"
#include "talus/solver/implicit_solver.hpp"

#include <gtest/gtest.h>

#include <malloc.h>

#include <cmath>
#include <string>

namespace {

using namespace talus;

double heap_in_use() {
  const struct mallinfo2 m = mallinfo2();
  return static_cast<double>(m.uordblks + m.hblkhd);
}

std::string case_text(const std::string& analysis, double cell, int ppc,
                      const std::string& model = "linear_elastic") {
  return "name: memory\nanalysis: " + analysis +
         "\ngrid: {extent: [10, 10], cell_size: " + std::to_string(cell) +
         "}\nmaterials:\n  - {name: m, model: " + model +
         ", density: 1000, youngs_modulus: 1.0e6, poisson_ratio: 0.3" +
         (model == "von_mises" ? ", yield_stress: 1.0e4" : "") +
         "}\nbodies:\n  - {name: block, material: m, shape: rectangle, min: [1, 1], max: [7, "
         "7], particles_per_cell: " +
         std::to_string(ppc) +
         "}\n  - {name: disc, material: m, shape: disc, centre: [8.5, 8.5], "
         "radius: 1}\ngravity: [0, -10]\nboundaries: {y_min: fixed}\n"
         "time: {end_time: 1, dt: 1.0e-4}\n";
}

struct Measured {
  double estimate = 0, real = 0;
  double points_estimated = 0;
  Index points = 0;
};

/// A 3D box resting on a fixed floor, 2 x 2 x 2 points per cell, solved by CHOLMOD (its 16.7k
/// unknowns would otherwise go to CG, whose steady heap after a step, 1.8 matrix copies, is
/// half the 3.7 the estimate takes from peak memory at 49k and 112k unknowns).
std::string case_text_3d(const std::string& analysis, double cell) {
  return "name: memory\ndimension: 3\nanalysis: " + analysis +
         "\ngrid: {extent: [4, 2, 2], cell_size: " + std::to_string(cell) +
         "}\nmaterials:\n  - {name: m, model: linear_elastic, density: 1000, youngs_modulus: "
         "1.0e6, poisson_ratio: 0.3}\nbodies:\n  - {name: block, material: m, shape: box, min: "
         "[0.5, 0, 0.5], max: [3.5, 1, 1.5], particles_per_cell: 2}\ngravity: [0, -10, 0]\n"
         "boundaries: {y_min: fixed}\ntime: {end_time: 1, dt: 1.0e-4}\n"
         "solver: {linear_solver: cholmod}\n";
}

template <int Dim> Measured measure(const std::string& text) {
  Measured m;
  const CaseSpec spec = read_case_text(text, "memory.yaml");
  const MemoryEstimate e = estimate_memory(spec);
  m.estimate = e.total_bytes;
  m.points_estimated = e.points;
  const double before = heap_in_use();
  double peak = 0;
  {
    Scene<Dim> scene = build_scene<Dim>(spec);
    m.points = scene.particles.size();
    if (spec.analysis == AnalysisType::Explicit) {
      auto solver = make_explicit_solver(scene);
      solver->step(1e-5);
      peak = heap_in_use() - before;
    } else {
      auto solver = make_implicit_solver(scene);
      solver->step(0.01, 0.01, 0.01);
      peak = heap_in_use() - before;
    }
  }
  m.real = peak;
  return m;
}

// The estimate must be neither far above (it would refuse cases that fit) nor far below (it
// would let through cases that do not). Measured ratios estimate / real heap (Release build,
// glibc 2.36): explicit 1.13 to 1.21 (the estimate carries one frame buffer, 72 B per point,
// that the test does not allocate), implicit 1.01 to 1.02 (the sparse factor's fill is a model,
// 8 n log2 n entries). glibc's accounting is deterministic, so the bounds [0.85, 1.35] can be
// tight enough to fail when an array of about a tenth of the heap is left out: without the
// implicit solver's per-point trial state the implicit ratio is 0.82 and the test fails (tried).
// Smaller parts (the vector growth of the point arrays, 3 %) are below what it resolves.
// In 3D the matrix and its factor dominate (about 80 % of the heap), so the 3D implicit
// variant checks the fill model of the factor (factor_entries_3d, n^1.8 fitted at 15.7k to
// 112k unknowns) and the matrix's rows of (2W - 1)^3 nodes: measured ratio 1.17 (with the
// 2D row of 25 nodes it would be about 0.7).
TEST(MemoryEstimate, MatchesTheHeapOfASmallScene) {
  struct Variant {
    std::string label, text;
    int dims = 2;
  };
  const Variant variants[] = {
      {"explicit, 2 points per cell", case_text("explicit", 0.05, 2)},
      {"explicit, 4 points per cell", case_text("explicit", 0.05, 4)},
      {"explicit, plastic", case_text("explicit", 0.05, 2, "von_mises")},
      {"implicit, 2 points per cell", case_text("implicit_quasistatic", 0.1, 2)},
      {"implicit, dynamic", case_text("implicit_dynamic", 0.1, 2)},
      {"implicit, 3D", case_text_3d("implicit_quasistatic", 0.1), 3},
  };
  for (const Variant& v : variants) {
    SCOPED_TRACE(v.label);
    const Measured m = v.dims == 2 ? measure<2>(v.text) : measure<3>(v.text);
    if (m.real == 0) // AddressSanitizer's allocator keeps mallinfo2 at zero
      GTEST_SKIP() << "the allocator reports no heap in use (a sanitizer build)";
    const double ratio = m.estimate / m.real;
    std::printf("%-28s points %lld (estimated %.0f), estimate %.3g B, heap %.3g B, ratio %.3f\n",
                v.label.c_str(), static_cast<long long>(m.points), m.points_estimated, m.estimate,
                m.real, ratio);
    EXPECT_NEAR(m.points_estimated, static_cast<double>(m.points), 0.02 * m.points);
    EXPECT_GT(ratio, 0.85);
    EXPECT_LT(ratio, 1.35);
  }
}

// Node storage follows the material: a small body in a grid of 200^3 cells (8.2e6 nodes) must
// not allocate anything per node of the grid. One 8-byte value per grid node would be 65 MB,
// the explicit solver's five arrays 850 MB; measured (Release, glibc 2.36) explicit 0.29 MB
// and implicit 2.6 MB of heap for the 512 points of a 4^3-cell body (estimates 0.38 and
// 10.8 MB, the factor's fill model dominating). The bound, 16 MB, holds the estimates and is a
// quarter of a single 8-byte value per grid node, so any per-grid-node array fails it (tried:
// one such array in the map, the former dense bins, gives 67 and 70 MB and fails).
TEST(MemoryEstimate, NodeStorageFollowsTheMaterial) {
  const std::string text =
      "name: sparse\ndimension: 3\nanalysis: ANALYSIS\ngrid: {extent: [20, 20, 20], "
      "cell_size: 0.1}\nmaterials:\n  - {name: m, model: linear_elastic, density: 1000, "
      "youngs_modulus: 1.0e6, poisson_ratio: 0.3}\nbodies:\n  - {name: block, material: m, "
      "shape: box, min: [0, 0, 0], max: [0.4, 0.4, 0.4], particles_per_cell: 2}\ngravity: [0, "
      "-10, 0]\nboundaries: {y_min: fixed}\ntime: {end_time: 1, dt: 1.0e-4}\n";
  for (const std::string analysis : {"explicit", "implicit_quasistatic"}) {
    SCOPED_TRACE(analysis);
    std::string t = text;
    t.replace(t.find("ANALYSIS"), 8, analysis);
    const Measured m = measure<3>(t);
    if (m.real == 0)
      GTEST_SKIP() << "the allocator reports no heap in use (a sanitizer build)";
    std::printf("%-22s points %lld, estimate %.3g B, heap %.3g B\n", analysis.c_str(),
                static_cast<long long>(m.points), m.estimate, m.real);
    EXPECT_EQ(m.points, 512);
    EXPECT_LT(m.real, 16e6);
    EXPECT_LT(m.estimate, 16e6);
  }
}

TEST(MemoryEstimate, CountsDoNotWrapAround) {
  const std::string text = case_text("explicit", 0.05, 2);
  const CaseSpec spec = read_case_text(text, "memory.yaml");
  CaseSpec huge = spec;
  huge.grid.extent = Vec3(1e15, 1e15, 0);
  huge.grid.cell_size = 1.0;
  const MemoryEstimate e = estimate_memory(huge);
  EXPECT_DOUBLE_EQ(e.cells_x, 1e15);
  EXPECT_GT(e.nodes, 1e30);
  // Nothing is stored per node of the grid: the small body's own nodes and points only.
  EXPECT_LT(e.active_nodes, 1e4);
  EXPECT_GT(e.total_bytes, 0.0);
  EXPECT_LT(e.total_bytes, 1e8);
}

TEST(MemoryEstimate, MachineMemoryIsRead) {
  const MachineMemory m = machine_memory();
  EXPECT_GT(m.total_bytes, 1e8);
  EXPECT_GT(m.available_bytes, 0.0);
  EXPECT_LE(m.available_bytes, m.total_bytes);
  EXPECT_FALSE(m.source.empty());
}

} // namespace
