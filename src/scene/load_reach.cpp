#include "load_reach.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <limits>

namespace talus {
namespace {

/// The box a prescribed box sweeps over its whole displacement (free components stay put).
template <int Dim> void swept_box(const PrescribedSpec& p, Vec<Dim>& lo, Vec<Dim>& hi) {
  lo = head<Dim>(p.min);
  hi = head<Dim>(p.max);
  for (int d = 0; d < Dim; ++d)
    if (const auto u = p.displacement[static_cast<std::size_t>(d)]) {
      lo[d] += std::min(0.0, *u);
      hi[d] += std::max(0.0, *u);
    }
}

template <int Dim>
double distance_to_box(const Vec<Dim>& x, const Vec<Dim>& lo, const Vec<Dim>& hi) {
  return (x.cwiseMax(lo).cwiseMin(hi) - x).norm();
}

/// Whether a corner of the cell that holds x (a node x's linear hat reaches) lies in [lo, hi].
template <int Dim>
bool cell_corner_in_box(const Vec<Dim>& x, const Vec<Dim>& origin, double h, const Vec<Dim>& lo,
                        const Vec<Dim>& hi) {
  const double tol = 1e-9 * h;
  for (int d = 0; d < Dim; ++d) {
    const double left = origin[d] + h * std::floor((x[d] - origin[d]) / h);
    const bool left_in = left >= lo[d] - tol && left <= hi[d] + tol;
    const bool right_in = left + h >= lo[d] - tol && left + h <= hi[d] + tol;
    if (!left_in && !right_in)
      return false;
  }
  return true;
}

template <int Dim> void check_prescribed_boxes(const Scene<Dim>& scene) {
  const CaseSpec& spec = scene.spec;
  const double h = scene.grid.cell_size();
  const Vec<Dim> origin = head<Dim>(spec.grid.origin);
  for (std::size_t i = 0; i < spec.prescribed.size(); ++i) {
    const PrescribedSpec& p = spec.prescribed[i];
    Vec<Dim> lo, hi;
    swept_box<Dim>(p, lo, hi);
    const auto& x = scene.particles.x;
    if (std::any_of(x.begin(), x.end(), [&](const Vec<Dim>& xp) {
          return cell_corner_in_box<Dim>(xp, origin, h, lo, hi);
        }))
      continue;
    double nearest = std::numeric_limits<double>::infinity();
    for (const Vec<Dim>& xp : x)
      nearest = std::min(nearest, distance_to_box<Dim>(xp, lo, hi));
    throw InputError(
        spec.location_of(fmt::format("prescribed[{}].min", i), p.where),
        fmt::format(
            "prescribed box '{}' reaches no material: none of its grid nodes, at the "
            "start or anywhere along its displacement, is a node of a cell that holds "
            "material points (the nearest point is {:.3g} m from the box, [{:g}] to [{:g}]), so "
            "it would carry no load; put the box on the body's nodes (a footing: the row "
            "of nodes at the surface under it)",
            p.name, nearest, fmt::join(lo, ", "), fmt::join(hi, ", ")));
  }
}

template <int Dim> void check_point_loads(const Scene<Dim>& scene) {
  const CaseSpec& spec = scene.spec;
  const double h = scene.grid.cell_size();
  for (std::size_t i = 0; i < spec.point_loads.size(); ++i) {
    const PointLoadSpec& load = spec.point_loads[i];
    const Vec<Dim> q = head<Dim>(load.point);
    double nearest = std::numeric_limits<double>::infinity();
    for (const Vec<Dim>& x : scene.particles.x)
      nearest = std::min(nearest, (x - q).norm());
    if (nearest > h)
      throw InputError(spec.location_of(fmt::format("point_loads[{}].point", i), load.where),
                       fmt::format("point load '{}' at [{:g}] reaches no material: the nearest "
                                   "material point is {:.3g} m away, more than a cell ({:g} m); "
                                   "the load acts on that point, so place it on the body",
                                   load.name, fmt::join(q, ", "), nearest, h));
  }
}

} // namespace

template <int Dim> void check_loads_reach_material(const Scene<Dim>& scene) {
  check_prescribed_boxes<Dim>(scene);
  check_point_loads<Dim>(scene);
}

template void check_loads_reach_material<2>(const Scene<2>&);
template void check_loads_reach_material<3>(const Scene<3>&);

} // namespace talus
