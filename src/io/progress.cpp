#include "talus/io/progress.hpp"

#include <algorithm>
#include <cstdio>
#include <fmt/format.h>
#include <unistd.h>

namespace talus {

namespace {
std::string format_seconds(double s) {
  if (!(s >= 0) || s > 1e7)
    return "--";
  const auto total = static_cast<long>(s + 0.5);
  if (total >= 3600)
    return fmt::format("{}h{:02}m", total / 3600, (total % 3600) / 60);
  if (total >= 60)
    return fmt::format("{}m{:02}s", total / 60, total % 60);
  return fmt::format("{}s", total);
}
} // namespace

void EtaEstimator::add(double fraction, double elapsed) {
  // One sample per half per cent of progress is enough for a rate, whatever the step count.
  constexpr double kSampleSpacing = 0.005, kWindow = 0.25;
  latest_ = {fraction, elapsed};
  if (fraction >= samples_.back().first + kSampleSpacing)
    samples_.emplace_back(fraction, elapsed);
  while (samples_.size() > 1 && samples_[1].first <= fraction - kWindow)
    samples_.pop_front();
}

double EtaEstimator::remaining_seconds() const {
  const auto& [f0, t0] = samples_.front();
  const auto& [f1, t1] = latest_;
  if (!(f1 > f0))
    return -1.0;
  // The rate (seconds per unit of progress) in the older and the newer half of the window,
  // extrapolated linearly to the middle of what is left: steps that keep getting dearer are
  // not underestimated by the lag of the window. The extrapolation stays within a factor of
  // two of the newer half's rate, so that noise in the rates cannot run away.
  const double rate = (t1 - t0) / (f1 - f0);
  const double fm = 0.5 * (f0 + f1);
  const auto middle = std::lower_bound(samples_.begin(), samples_.end(), fm,
                                       [](const auto& s, double f) { return s.first < f; });
  if (middle == samples_.begin() || middle == samples_.end() || !(middle->first < f1))
    return rate * (1.0 - f1);
  const auto& [fa, ta] = *middle;
  const double older = (ta - t0) / (fa - f0), newer = (t1 - ta) / (f1 - fa);
  const double slope = (newer - older) / (0.5 * (f1 - f0));
  const double ahead = newer + slope * (0.5 * (1.0 + f1) - 0.5 * (fa + f1));
  return std::clamp(ahead, 0.5 * newer, 2.0 * newer) * (1.0 - f1);
}

Progress::Progress(std::string label, double end_time, bool enabled)
    : label_(std::move(label)), end_time_(end_time), enabled_(enabled),
      terminal_(isatty(fileno(stderr)) != 0), start_(std::chrono::steady_clock::now()),
      last_draw_(start_) {}

void Progress::update(Index step, double time, double dt, const std::string& extra) {
  if (!enabled_)
    return;
  const auto now = std::chrono::steady_clock::now();
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double fraction = end_time_ > 0 ? time / end_time_ : 0.0;
  eta_.add(fraction, elapsed);
  const double eta = eta_.remaining_seconds();
  const std::string line =
      fmt::format("{} step {} t={:.4g}/{:.4g} dt={:.3g} {:5.1f}% elapsed {} ETA {}{}{}", label_,
                  step, time, end_time_, dt, 100.0 * fraction, format_seconds(elapsed),
                  format_seconds(eta), extra.empty() ? "" : " ", extra);
  if (terminal_) {
    if (std::chrono::duration<double>(now - last_draw_).count() < 0.2)
      return;
    last_draw_ = now;
    std::fprintf(stderr, "\r\033[K%s", line.c_str());
    std::fflush(stderr);
  } else if (fraction * 10.0 >= next_decile_) {
    while (fraction * 10.0 >= next_decile_)
      ++next_decile_;
    std::fprintf(stderr, "%s\n", line.c_str());
  }
}

void Progress::finish(const std::string& final_message) {
  if (!enabled_)
    return;
  if (terminal_)
    std::fprintf(stderr, "\r\033[K");
  std::fprintf(stderr, "%s %s\n", label_.c_str(), final_message.c_str());
}

} // namespace talus
