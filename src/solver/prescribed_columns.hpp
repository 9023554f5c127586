#pragma once
// Internal to the run recorder (run_recorder.hpp): a prescribed box's columns in timeseries.csv
// beside its reaction: the displacement given to it so far, and the mean pressure on it. The
// pressure is the reaction over the box's face in the geometry's own measure: per metre of
// thickness in plane strain, per radian in axisymmetry, the area in 3D, so that it is the same
// for a half or a quarter model as for the whole (docs/output-format.md).
#include "talus/spec/case_spec.hpp"

#include <cmath>
#include <fmt/format.h>
#include <string>
#include <vector>

namespace talus::run_detail {

/// The measure of the face of `box` normal to `axis` (the width across in plane strain, the
/// annulus (r2^2 - r1^2) / 2 or the band r dz per radian in axisymmetry, the area in 3D); zero
/// when the box has no extent across.
inline double prescribed_face_measure(const CaseSpec& spec, const PrescribedSpec& box, int axis) {
  const Vec3 size = box.max - box.min;
  if (spec.dimension == 3)
    return size[(axis + 1) % 3] * size[(axis + 2) % 3];
  if (spec.geometry != Geometry::Axisymmetric)
    return size[1 - axis];
  if (axis == 1)
    return 0.5 * (box.max.x() * box.max.x() - box.min.x() * box.min.x());
  return 0.5 * (box.min.x() + box.max.x()) * size.y();
}

/// Calls f(axis, has_pressure) for each prescribed component of `box`.
template <class F>
void for_each_prescribed_axis(const CaseSpec& spec, const PrescribedSpec& box, F&& f) {
  for (int a = 0; a < spec.dimension; ++a)
    if (box.displacement[static_cast<std::size_t>(a)])
      f(a, prescribed_face_measure(spec, box, a) > 0.0);
}

/// The column names: displacement_<box>_<axis> and, where the box has a face across,
/// pressure_<box>_<axis>.
inline void append_prescribed_columns(const CaseSpec& spec, const PrescribedSpec& box,
                                      std::vector<std::string>& cols) {
  for_each_prescribed_axis(spec, box, [&](int a, bool pressure) {
    cols.push_back(fmt::format("displacement_{}_{}", box.name, "xyz"[a]));
    if (pressure)
      cols.push_back(fmt::format("pressure_{}_{}", box.name, "xyz"[a]));
  });
}

/// Their values, at the fraction of the prescribed displacement reached and for the box's
/// reaction (the force on the body): the pressure is positive when the box pushes into the body
/// along its displacement (a held box: the reaction's component over the face).
inline void append_prescribed_values(const CaseSpec& spec, const PrescribedSpec& box,
                                     double fraction, const Vec3& reaction,
                                     std::vector<double>& row) {
  for_each_prescribed_axis(spec, box, [&](int a, bool pressure) {
    const double full = *box.displacement[static_cast<std::size_t>(a)];
    // + 0.0 turns the first row's -0 into 0.
    row.push_back(fraction * full + 0.0);
    if (pressure)
      row.push_back(std::copysign(1.0, full) * reaction[a] / prescribed_face_measure(spec, box, a) +
                    0.0);
  });
}

} // namespace talus::run_detail
