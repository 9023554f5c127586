#pragma once
// Progress of a long run: one updating line on a terminal, a plain log line every ~10 % of the
// run otherwise (logs and CI stay readable).
#include "talus/core/types.hpp"

#include <chrono>
#include <deque>
#include <string>
#include <utility>

namespace talus {

/// The time a run has left, from its progress since its first step (which starts everything
/// up and is no guide to the others). The time per unit of progress (the rate) is fitted by a
/// least-squares line over the last third of the run. A rising line is extrapolated to the
/// end: costs that rise are real (an implicit run's steps take more Newton iterations as the
/// soil yields; an explicit run's points split and move faster). A falling line is taken at
/// its value now and not further: a falling cost is mostly a start-up passing. The rate stays
/// within [1/2, 2] times the window's mean rate, so that a noisy slope over a few samples cannot
/// run away, and gets a fifth more, for the rise the window has not seen yet. Measured against
/// the shipped cases in docs/performance.md.
class EtaEstimator {
public:
  /// The run is `fraction` (0 to 1) done after `elapsed` seconds.
  void add(double fraction, double elapsed);
  /// Seconds left, or -1 before there is a rate.
  double remaining_seconds() const;

private:
  /// (fraction, elapsed) at least half a per cent apart, over the last third of the run and
  /// from the first step's end until a third is done.
  std::deque<std::pair<double, double>> samples_;
  std::pair<double, double> latest_{0.0, 0.0};
};

class Progress {
public:
  Progress(std::string label, double end_time, bool enabled);
  /// `extra` is appended to the line, e.g. "newton 3".
  void update(Index step, double time, double dt, const std::string& extra = {});
  void finish(const std::string& final_message);

private:
  std::string label_;
  double end_time_;
  bool enabled_;
  bool terminal_;
  std::chrono::steady_clock::time_point start_, last_draw_;
  int next_decile_ = 1;
  EtaEstimator eta_;
};

} // namespace talus
