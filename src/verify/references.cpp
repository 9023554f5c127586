#include "references.hpp"

#include <cmath>
#include <fmt/format.h>
#include <numbers>

namespace talus::references {

double cantilever_deflection(double x, double P) {
  return -P / (6.0 * kBeamYoung * kBeamInertia) *
         (kBeamDepth * kBeamDepth * x + (3.0 * kBeamLength - x) * x * x);
}

Vec2 tip_column_displacement(const ResultsReader& results, double* tip_x) {
  Index rows = 0, cols = 0;
  const auto x0 = results.read(0, "position", &rows, &cols);
  const auto x1 = results.read(results.frame_count() - 1, "position", &rows, &cols);
  auto at = [](const std::vector<double>& xy, Index p) {
    return Vec2(xy[static_cast<std::size_t>(2 * p)], xy[static_cast<std::size_t>(2 * p + 1)]);
  };
  double xmax = -1e300;
  for (Index p = 0; p < rows; ++p)
    xmax = std::max(xmax, at(x0, p).x());
  Vec2 sum = Vec2::Zero();
  int n = 0;
  for (Index p = 0; p < rows; ++p)
    if (std::abs(at(x0, p).x() - xmax) < 1e-9) {
      sum += at(x1, p) - at(x0, p);
      ++n;
    }
  *tip_x = xmax;
  return sum / n;
}

double vibrating_bar_rms_error(const CsvTable& series, double total_mass) {
  const double b1 = std::numbers::pi / (2.0 * kBarLength);
  const double w1 = b1 * std::sqrt(kBarYoung / kBarDensity);
  const double amplitude = kBarV0 / (b1 * kBarLength);
  const auto& t = series.column("time");
  const auto& dt = series.column("dt");
  const auto& px = series.column("momentum_x");
  double sum = 0;
  for (std::size_t i = 0; i < t.size(); ++i) {
    const double e = px[i] / total_mass - amplitude * std::cos(w1 * (t[i] - 0.5 * dt[i]));
    sum += e * e;
  }
  return std::sqrt(sum / static_cast<double>(t.size())) / amplitude;
}

std::vector<std::string> vibrating_bar_overrides(int n) {
  const double h = kBarLength / n;
  return {fmt::format("grid.cell_size={:.17g}", h),
          fmt::format("grid.extent=[{:.17g}, {:.17g}]", kBarLength + 2 * h, h),
          fmt::format("bodies.bar.max=[{:.17g}, {:.17g}]", kBarLength, h)};
}

} // namespace talus::references
