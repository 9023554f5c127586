#pragma once
// Internal to run_case: the length of an implicit stage's load steps. Halved when Newton fails,
// down to time.min_dt; doubled back towards time.dt after two easy steps in a row (at most
// solver.easy_newton_iterations iterations each), so a step cut back at a hard stretch of the
// loading grows again once the loading is easy.
#include "run_state.hpp"
#include "talus/spec/case_spec.hpp"

#include <algorithm>

namespace talus::run_detail {

class LoadStepController {
public:
  /// `state`: where the controller keeps its step and count (the loop's, checkpointed).
  LoadStepController(const TimeSpec& time, int easy_iterations, LoadStepControl& state)
      : dt0_(*time.dt), min_dt_(time.smallest_step()), easy_(easy_iterations), state_(state) {}

  /// A stage starts with time.dt.
  void start() { state_ = {dt0_, 0}; }
  double dt() const { return state_.dt; }

  /// After an attempt of length `step_dt` that failed: false when it was already the smallest
  /// step (the stepper then stalls), else the step is halved.
  bool cut_back(double step_dt) {
    state_.easy_steps = 0;
    if (step_dt <= min_dt_ * (1.0 + 1e-12))
      return false;
    state_.dt = std::max(0.5 * step_dt, min_dt_);
    return true;
  }

  /// After a step that converged in `iterations` Newton iterations.
  void converged(int iterations) {
    if (iterations <= easy_ && ++state_.easy_steps >= 2) {
      state_.dt = std::min(2.0 * state_.dt, dt0_);
      state_.easy_steps = 0;
    } else if (iterations > easy_) {
      state_.easy_steps = 0;
    }
  }

private:
  double dt0_, min_dt_;
  int easy_;
  LoadStepControl& state_;
};

} // namespace talus::run_detail
