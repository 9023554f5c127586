#pragma once
// A scope's wall time added to a running total: the phase timers of the implicit solver and of
// Newton's linear solves (summary.json `seconds_*`).
#include <chrono>

namespace talus {

/// Adds the seconds from its construction to its destruction to `total`.
class AddSeconds {
public:
  explicit AddSeconds(double& total) : total_(total) {}
  ~AddSeconds() {
    total_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }
  AddSeconds(const AddSeconds&) = delete;
  AddSeconds& operator=(const AddSeconds&) = delete;

private:
  double& total_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

} // namespace talus
