#include "references.hpp"

#include <cmath>
#include <fmt/format.h>
#include <numbers>

namespace talus::references {

double cantilever_deflection(double x, double P, double nu) {
  return -P / (6.0 * kBeamYoung * kBeamInertia) *
         ((4.0 + 5.0 * nu) / 4.0 * kBeamDepth * kBeamDepth * x + (3.0 * kBeamLength - x) * x * x);
}

Vec3 tip_column_displacement(const ResultsReader& results, double* tip_x) {
  Index rows = 0, cols = 0;
  const auto x0 = results.read(0, "position", &rows, &cols);
  const auto x1 = results.read(results.frame_count() - 1, "position", &rows, &cols);
  auto at = [cols](const std::vector<double>& x, Index p) {
    Vec3 v = Vec3::Zero();
    for (Index d = 0; d < cols; ++d)
      v[d] = x[static_cast<std::size_t>(cols * p + d)];
    return v;
  };
  double xmax = -1e300;
  for (Index p = 0; p < rows; ++p)
    xmax = std::max(xmax, at(x0, p).x());
  Vec3 sum = Vec3::Zero();
  int n = 0;
  for (Index p = 0; p < rows; ++p)
    if (std::abs(at(x0, p).x() - xmax) < 1e-9) {
      sum += at(x1, p) - at(x0, p);
      ++n;
    }
  *tip_x = xmax;
  return sum / n;
}

// theta'' = -alpha cos(theta) on s in [0, 1], theta(0) = 0, theta'(1) = 0 (free end); the
// displacement of the point at arclength s_end (a multiple of 1/4000 up to round-off).
Elastica elastica(double alpha, double s_end) {
  const int n = 4000;
  const int i_end = static_cast<int>(std::lround(s_end * n));
  double x_end = 0, y_end = 0;
  auto shoot = [&](double k0, double& x, double& y) {
    const double h = 1.0 / n;
    double th = 0, k = k0;
    x = y = 0;
    for (int i = 0; i < n; ++i) {
      if (i == i_end) {
        x_end = x;
        y_end = y;
      }
      const double t1 = th, k1 = k;
      const double t2 = th + 0.5 * h * k1, k2 = k - 0.5 * h * alpha * std::cos(t1);
      const double t3 = th + 0.5 * h * k2, k3 = k - 0.5 * h * alpha * std::cos(t2);
      const double t4 = th + h * k3, k4 = k - h * alpha * std::cos(t3);
      x += h / 6 * (std::cos(t1) + 2 * std::cos(t2) + 2 * std::cos(t3) + std::cos(t4));
      y += h / 6 * (std::sin(t1) + 2 * std::sin(t2) + 2 * std::sin(t3) + std::sin(t4));
      th += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
      k -= h / 6 * alpha * (std::cos(t1) + 2 * std::cos(t2) + 2 * std::cos(t3) + std::cos(t4));
    }
    if (i_end >= n) {
      x_end = x;
      y_end = y;
    }
    return k; // theta'(1)
  };
  double lo = 0, hi = alpha, x = 0, y = 0;
  for (int it = 0; it < 60; ++it) {
    const double mid = 0.5 * (lo + hi);
    (shoot(mid, x, y) > 0 ? hi : lo) = mid;
  }
  shoot(0.5 * (lo + hi), x, y);
  return {static_cast<double>(i_end) / n - x_end, y_end};
}

std::vector<std::string> large_deflection_overrides(double alpha, int steps, int depth_cells) {
  const double D = kSlenderBeamDepth;
  const double P = alpha * kBeamYoung * (D * D * D / 12.0) / (kBeamLength * kBeamLength);
  return {"materials.beam.model=hencky",
          fmt::format("bodies[0].min=[0, {:.17g}]", -0.5 * D),
          fmt::format("bodies[0].max=[{:.17g}, {:.17g}]", kBeamLength, 0.5 * D),
          fmt::format("grid.cell_size={:.17g}", D / depth_cells),
          fmt::format("tractions[0].traction=[0, {:.17g}]", -P / D),
          fmt::format("time.dt={:.17g}", 1.0 / steps),
          "grid.extent=[10, 9]",
          "grid.origin=[0, -8]",
          "output.every_steps=1000000"};
}

double large_deflection_error(const ResultsReader& results, double alpha) {
  double x = 0;
  const Vec3 u = tip_column_displacement(results, &x);
  const Elastica ref = elastica(alpha, x / kBeamLength);
  return std::max(std::abs(-u.x() / kBeamLength / ref.u_over_L - 1.0),
                  std::abs(-u.y() / kBeamLength / ref.v_over_L - 1.0));
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

std::vector<std::string> vibrating_bar_overrides(int n, int dimension, int height_cells) {
  const double h = kBarLength / n;
  const double height = height_cells * h;
  const std::string depth = dimension == 3 ? fmt::format(", {:.17g}", height) : "";
  return {fmt::format("grid.cell_size={:.17g}", h),
          fmt::format("grid.extent=[{:.17g}, {:.17g}{}]", kBarLength + 2 * h, height, depth),
          fmt::format("bodies.bar.max=[{:.17g}, {:.17g}{}]", kBarLength, height, depth)};
}

namespace {

/// The stretch at initial height Y: the root of M ln(l) / l = sigma in (0, 1] (the left side
/// increases monotonically there), by bisection to round-off.
double exact_stretch(double Y, double E) {
  const double M = E * (1 - kColumnPoisson) / ((1 + kColumnPoisson) * (1 - 2 * kColumnPoisson));
  const double sigma = -kColumnDensity * kColumnGravity * (kColumnHeight - Y);
  double lo = 1e-6, hi = 1.0;
  for (int i = 0; i < 200 && hi - lo > 1e-16; ++i) {
    const double mid = 0.5 * (lo + hi);
    (M * std::log(mid) / mid > sigma ? hi : lo) = mid;
  }
  return 0.5 * (lo + hi);
}

/// u(Y) by Simpson's rule (lambda is smooth in Y).
double exact_displacement(double Y, double E) {
  return simpson([E](double y) { return exact_stretch(y, E) - 1.0; }, 0.0, Y);
}

} // namespace

double simpson(const std::function<double(double)>& f, double a, double b, int intervals) {
  const double step = (b - a) / intervals;
  double sum = 0;
  for (int i = 0; i <= intervals; ++i) {
    const double weight = (i == 0 || i == intervals) ? 1 : (i % 2 == 1 ? 4 : 2);
    sum += weight * f(a + i * step);
  }
  return sum * step / 3.0;
}

std::vector<std::string> compressed_column_overrides(int n, double ratio) {
  const double h = kColumnHeight / n;
  const double E = kColumnDensity * kColumnGravity * kColumnHeight / ratio;
  return {fmt::format("grid.cell_size={:.17g}", h),
          fmt::format("grid.extent=[{:.17g}, {:.17g}]", 4 * h, kColumnHeight + 4 * h),
          fmt::format("bodies[0].max=[{:.17g}, {:.17g}]", 4 * h, kColumnHeight),
          fmt::format("materials[0].youngs_modulus={:.17g}", E)};
}

ColumnErrors compressed_column_errors(const ResultsReader& results, double ratio) {
  const double E = kColumnDensity * kColumnGravity * kColumnHeight / ratio;
  Index rows = 0, dims = 0, cols = 0;
  const auto x0 = results.read(0, "position", &rows, &dims);
  const auto volume = results.read(0, "volume", &rows, &cols);
  const Index last = results.frame_count() - 1;
  const auto x = results.read(last, "position", &rows, &dims);
  const auto raw = results.read(last, "stress", &rows, &cols);
  const auto smoothed = results.read(last, "stress_smoothed", &rows, &cols);
  double raw_error = 0, smooth_error = 0, norm = 0, top = -1, top_u = 0;
  int top_count = 0;
  const auto D = static_cast<std::size_t>(dims), C = static_cast<std::size_t>(cols);
  for (Index p = 0; p < rows; ++p) {
    const auto s = static_cast<std::size_t>(p);
    const double Y = x0[D * s + 1];
    const double exact = -kColumnDensity * kColumnGravity * (kColumnHeight - Y);
    raw_error += volume[s] * std::pow(raw[s * C + 3] - exact, 2); // xx, xy, xz, yy, ...
    smooth_error += volume[s] * std::pow(smoothed[s * C + 3] - exact, 2);
    norm += volume[s] * exact * exact;
    if (Y > top + 1e-9) {
      top = Y;
      top_u = 0;
      top_count = 0;
    }
    if (std::abs(Y - top) <= 1e-9) {
      top_u += x[D * s + 1] - Y;
      ++top_count;
    }
  }
  const double exact_top = exact_displacement(top, E);
  return {std::sqrt(raw_error / norm), std::sqrt(smooth_error / norm),
          (top_u / top_count - exact_top) / std::abs(exact_top)};
}

} // namespace talus::references
