#pragma once
// Progress of a long run: one updating line on a terminal, a plain log line every ~10 % of the
// run otherwise (logs and CI stay readable).
#include "talus/core/types.hpp"

#include <chrono>
#include <string>

namespace talus {

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
};

} // namespace talus
