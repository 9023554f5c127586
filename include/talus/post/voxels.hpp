#pragma once
// Deformed voxels and colour patterns (Andersen 2013): every material point starts as a
// rectangle of the initial particle lattice (its voxel, half-sizes `half_size0` about `x0`);
// the deformation gradient maps it to the parallelogram with corners x_p + F_p (X_c - X_p),
// which shows the deformation a cloud of dots hides. Dummy colour patterns painted on the
// initial lattice (checkerboard, horizontal and vertical stripes) make the deformation readable.
#include "talus/core/particles.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace talus {

template <int Dim> struct Voxels {
  static constexpr int kCorners = 1 << Dim;
  /// Per particle the deformed corners. 2D: counter-clockwise from the initial (-, -) corner,
  /// (-, -), (+, -), (+, +), (-, +). 3D: that square at z - and then at z + (VTK's hexahedron
  /// order).
  Array<std::array<Vec<Dim>, kCorners>> corners;
  /// Pattern colour (0 or 1) per particle, from the square (cube) of side `pattern_size` of the
  /// initial lattice that holds x0: checker alternates in every direction, horizontal stripes in
  /// y only, vertical stripes in x only.
  std::vector<std::int32_t> checker, stripes_horizontal, stripes_vertical;
};

/// Fills `voxels` for the current state, reusing its storage from earlier frames; the pattern
/// squares start at `pattern_origin` (the grid origin).
template <int Dim>
void update_voxels(const Particles<Dim>& particles, const Vec<Dim>& pattern_origin,
                   double pattern_size, Voxels<Dim>& voxels);

} // namespace talus
