#pragma once
// Progress of a long run: one updating line on a terminal, a plain log line every ~10 % of the
// run otherwise (logs and CI stay readable).
#include "talus/core/types.hpp"

#include <chrono>
#include <deque>
#include <string>
#include <utility>

namespace talus {

/// The time a run has left, from its progress so far. It extrapolates the rate of the last
/// quarter of the run rather than the average: an implicit run's steps get dearer as the soil
/// yields (more Newton iterations, cut-backs near a limit load), and an explicit run's cheaper
/// once its start-up is behind it.
class EtaEstimator {
public:
  /// The run is `fraction` (0 to 1) done after `elapsed` seconds.
  void add(double fraction, double elapsed);
  /// Seconds left, or -1 before there is a rate.
  double remaining_seconds() const;

private:
  /// (fraction, elapsed) at least half a per cent apart, over the last quarter of the run and
  /// from the run's start until a quarter is done.
  std::deque<std::pair<double, double>> samples_{{0.0, 0.0}};
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
