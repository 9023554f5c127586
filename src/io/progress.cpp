#include "talus/io/progress.hpp"

#include <algorithm>
#include <cstdio>
#include <fmt/format.h>
#include <unistd.h>
#include <vector>

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
  constexpr double kSampleSpacing = 0.005, kWindow = 0.35;
  latest_ = {fraction, elapsed};
  if (samples_.empty()) { // the first step, which starts everything up, sets the origin
    samples_.emplace_back(fraction, elapsed);
    return;
  }
  if (fraction >= samples_.back().first + kSampleSpacing)
    samples_.emplace_back(fraction, elapsed);
  while (samples_.size() > 1 && samples_[1].first <= fraction - kWindow)
    samples_.pop_front();
}

double EtaEstimator::remaining_seconds() const {
  if (samples_.empty())
    return -1.0;
  const auto [f0, t0] = samples_.front();
  const auto [f1, t1] = latest_;
  if (!(f1 > f0))
    return -1.0;
  const double mean_rate = (t1 - t0) / (f1 - f0);
  // The rate of each interval between samples (the latest state closing the last), at the
  // interval's middle, weighted by its length: a weighted least-squares line whose mean is
  // the window's mean rate.
  std::vector<std::pair<double, double>> points(samples_.begin(), samples_.end());
  if (f1 > points.back().first)
    points.push_back(latest_);
  double sxx = 0, sxy = 0, centre = 0;
  for (std::size_t k = 1; k < points.size(); ++k)
    centre +=
        (points[k].first - points[k - 1].first) * 0.5 * (points[k].first + points[k - 1].first);
  centre /= f1 - f0;
  for (std::size_t k = 1; k < points.size(); ++k) {
    const auto [a, ta] = points[k - 1];
    const auto [b, tb] = points[k];
    const double x = 0.5 * (a + b) - centre, rate = (tb - ta) / (b - a);
    sxx += (b - a) * x * x;
    sxy += (b - a) * x * (rate - mean_rate);
  }
  // Costs that rise beyond what the window has seen are the rule in the runs measured
  // (docs/performance.md): a fifth more balances the estimate's errors about the truth.
  constexpr double kMargin = 1.2;
  constexpr std::size_t kFewestIntervals = 3;
  if (points.size() <= kFewestIntervals || !(sxx > 0))
    return kMargin * mean_rate * (1.0 - f1);
  // A rising line is followed to the end (its mean over what is left: its value now plus half
  // its rise); a falling one only to now. Within [1/2, 2] of the mean rate.
  const double slope = sxy / sxx;
  const double ahead = mean_rate + slope * (f1 - centre + (slope > 0 ? 0.5 * (1.0 - f1) : 0.0));
  return kMargin * std::clamp(ahead, 0.5 * mean_rate, 2.0 * mean_rate) * (1.0 - f1);
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
