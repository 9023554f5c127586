#pragma once
// Internal to run_case: the state a run's loops step with and a checkpoint keeps. The loops
// hold these structs themselves (LoopState, Recorder, the load-step controller's state), and a
// checkpoint's RunProgress holds them as they are, so saving and resuming copy whole structs.
#include "talus/core/types.hpp"
#include "talus/solver/implicit_solver.hpp"

#include <limits>

namespace talus::run_detail {

/// An implicit stage's step length and how many easy steps in a row it has taken
/// (LoadStepController).
struct LoadStepControl {
  double dt = 0;
  int easy_steps = 0;
};

/// Where the stepping is: time, step counts, the implicit step's control and continuation, and
/// the current stiffness of a run that measures it.
struct LoopCounters {
  double t = 0;               ///< the stage's time
  Index step = 0;             ///< steps of the whole run
  Index stage_first_step = 0; ///< `step` when the current stage began
  LoadStepControl load_step{};
  ImplicitSolver::Continuation continuation{};
  /// RunOptions::measure_stiffness: the reference compliance (the run's first measured step)
  /// and the last step's current stiffness, reference / its compliance (NaN: none yet).
  double reference_compliance = std::numeric_limits<double>::quiet_NaN();
  double current_stiffness = std::numeric_limits<double>::quiet_NaN();
};

/// The output schedule of the recorder and what writing frames has cost so far.
struct FrameSchedule {
  double next_frame_time = 0;
  bool frame_at_current_step = true;
  Index last_frame_step = 0;
  double last_frame_time = 0;
  double post_seconds = 0;  ///< stress recovery and voxels, the frames' post-processing
  double frame_seconds = 0; ///< writing frames, post-processing included
};

} // namespace talus::run_detail
