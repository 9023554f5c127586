#pragma once
// How long a case will roughly take, from its CaseSpec and memory estimate alone: the steps each
// stage takes (an implicit stage's load steps, an explicit stage's CFL-limited steps), times a
// measured cost per point-step (explicit) or per unknown and Newton iteration (implicit). The
// costs were measured on the project's 2-core machine (docs/performance.md); the figure is meant
// to tell seconds from hours, not to schedule a run (docs/case-format.md, checking a case).
#include "talus/scene/memory_estimate.hpp"
#include "talus/spec/case_spec.hpp"

#include <string>

namespace talus {

struct RunTimeEstimate {
  double steps = 0;           ///< time or load steps over every stage
  double unknowns = 0;        ///< implicit: Dim x the active nodes of the first step; else 0
  double newton_per_step = 0; ///< implicit: the Newton iterations assumed per load step
  /// implicit: whether the tangent is symmetric (no F-bar, associated flow, no softening), so
  /// that Cholesky can factor it
  bool symmetric = true;
  double seconds = 0;       ///< the whole run on `threads` threads, start_seconds included
  double start_seconds = 0; ///< of which starting the process and building the scene
  /// "about 40 s (3,000 steps of 1,536 points)".
  std::string describe() const;
};

RunTimeEstimate estimate_run_time(const CaseSpec& spec, const MemoryEstimate& memory, int threads);

} // namespace talus
