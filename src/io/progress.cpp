#include "talus/io/progress.hpp"

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
  const double eta = fraction > 0 ? elapsed * (1.0 - fraction) / fraction : -1.0;
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
