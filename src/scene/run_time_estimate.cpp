// A rough run time (talus/scene/run_time_estimate.hpp).
#include "talus/scene/run_time_estimate.hpp"

#include "talus/material/material.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <utility>
#include <vector>

namespace talus {
namespace {

// Explicit throughput, million point-steps per second with GIMP and MUSL on two threads
// (docs/performance.md: 9.4 in 2D, 2.4 to 3.0 in 3D); one thread gives about 0.6 of it. Each
// step also costs about a millisecond whatever its points (the grid's passes, the frames' and
// OpenMP's bookkeeping): measured 1.7 ms per step on the colliding discs' 460 steps and the
// soil column's 6779.
constexpr double kPointStepsPerSecond2d = 9e6, kPointStepsPerSecond3d = 2.5e6;
constexpr double kOneThreadShare = 0.6;
constexpr double kSecondsPerStep = 1e-3;
// Starting the process (loading the libraries, building the scene, the first frame): about
// 0.3 s for the shipped 2D cases.
constexpr double kStartSeconds = 0.3;
// A Newton iteration (material update, assembly, factorisation and solve) per unknown on two
// threads. Symmetric tangents (CHOLMOD): 2.2 us in 2D (cantilever_large, 1234 unknowns; 2.5 us
// at 4068), 16 us in 3D (a Hencky cantilever, 2984 unknowns). Nonsymmetric ones (UMFPACK: F-bar,
// non-associated flow) factor about 7 times slower: 15 us in 2D (the strip and circular
// footings, 4384 unknowns, 130 ms per iteration on a busy machine), and 3D is taken 7 times its
// symmetric cost too. A direct factorisation grows faster than the unknowns.
constexpr double kIterationPerUnknown2d = 2.2e-6, kIterationPerUnknown3d = 1.6e-5;
constexpr double kNonsymmetricFactor = 7;
constexpr double kReferenceUnknowns2d = 1234, kReferenceUnknowns3d = 2984;
constexpr double kGrowth2d = 0.1, kGrowth3d = 0.5;
// Newton iterations per load step: about 4 for elastic bodies, more where the soil yields
// (6.5 on the strip footing's 40 steps, 6.1 on the circular footing's 25).
constexpr double kNewtonElastic = 4, kNewtonPlastic = 8;

/// The largest P-wave speed of the case's materials, m/s (the explicit CFL limit's).
double p_wave_speed(const CaseSpec& spec) {
  double c = 0;
  for (const MaterialSpec& m : spec.materials) {
    const auto lame = LameParameters::from_young_poisson(m.youngs_modulus, m.poisson_ratio);
    c = std::max(c, std::sqrt(lame.p_wave_modulus() / m.density));
  }
  return c;
}

double stage_steps(const CaseSpec& spec, AnalysisType analysis, const TimeSpec& time) {
  double dt = time.dt.value_or(0.0);
  if (!time.dt && analysis == AnalysisType::Explicit) {
    const double c = p_wave_speed(spec);
    dt = c > 0 ? time.cfl.value_or(0.5) * spec.grid.cell_size / c : time.end_time;
  }
  return dt > 0 ? std::ceil(time.end_time / dt * (1.0 - 1e-12)) : 1.0;
}

std::string seconds_text(double s) {
  if (s < 1)
    return "under a second";
  if (s < 90)
    return fmt::format("about {:.2g} s", s);
  if (s < 5400)
    return fmt::format("about {:.2g} min", s / 60);
  return fmt::format("about {:.2g} h", s / 3600);
}

} // namespace

std::string RunTimeEstimate::describe() const {
  if (unknowns > 0)
    return fmt::format("{} ({:.4g} load steps of {:.4g} unknowns, {:g} Newton iterations each)",
                       seconds_text(seconds), steps, unknowns, newton_per_step);
  return fmt::format("{} ({:.4g} steps)", seconds_text(seconds), steps);
}

RunTimeEstimate estimate_run_time(const CaseSpec& spec, const MemoryEstimate& memory, int threads) {
  RunTimeEstimate e;
  e.start_seconds = e.seconds = kStartSeconds;
  const bool three_d = spec.dimension == 3;
  const double share = threads >= 2 ? 1.0 : kOneThreadShare;
  const bool plastic = std::any_of(spec.materials.begin(), spec.materials.end(),
                                   [](const MaterialSpec& m) { return is_plastic(m.model); });
  const double unknowns = (spec.dimension + (spec.consolidates() ? 1 : 0)) * memory.active_nodes;
  e.symmetric = symmetric_implicit_tangent(spec);
  const double per_unknown = (three_d ? kIterationPerUnknown3d : kIterationPerUnknown2d) *
                             (e.symmetric ? 1.0 : kNonsymmetricFactor);
  const double growth =
      std::pow(std::max(1.0, unknowns / (three_d ? kReferenceUnknowns3d : kReferenceUnknowns2d)),
               three_d ? kGrowth3d : kGrowth2d);
  const double iteration = per_unknown * unknowns * growth / share;
  const double point_step =
      1.0 / ((three_d ? kPointStepsPerSecond3d : kPointStepsPerSecond2d) * share);
  std::vector<std::pair<AnalysisType, TimeSpec>> stages;
  if (spec.stages.empty())
    stages.emplace_back(spec.analysis, spec.time);
  for (const StageSpec& s : spec.stages)
    stages.emplace_back(s.analysis, s.time);
  for (const auto& [analysis, time] : stages) {
    const double steps = stage_steps(spec, analysis, time);
    e.steps += steps;
    if (analysis == AnalysisType::Explicit) {
      e.seconds += steps * (memory.points * point_step + kSecondsPerStep);
    } else {
      e.unknowns = unknowns;
      e.newton_per_step = plastic ? kNewtonPlastic : kNewtonElastic;
      e.seconds += steps * e.newton_per_step * iteration;
    }
  }
  return e;
}

} // namespace talus
