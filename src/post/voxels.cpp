// Deformed voxels and colour patterns (include/talus/post/voxels.hpp).
#include "talus/post/voxels.hpp"

#include "talus/core/parallel.hpp"

#include <cmath>

namespace talus {

namespace {

/// Corner offsets X_c - X_p in units of the half-sizes, in the order of Voxels::corners.
template <int Dim> std::array<Vec<Dim>, Voxels<Dim>::kCorners> corner_signs() {
  static const double square[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  std::array<Vec<Dim>, Voxels<Dim>::kCorners> signs;
  for (std::size_t c = 0; c < signs.size(); ++c) {
    signs[c][0] = square[c % 4][0];
    signs[c][1] = square[c % 4][1];
    if constexpr (Dim == 3)
      signs[c][2] = c < 4 ? -1.0 : 1.0;
  }
  return signs;
}

} // namespace

template <int Dim>
void update_voxels(const Particles<Dim>& particles, const Vec<Dim>& pattern_origin,
                   double pattern_size, Voxels<Dim>& v) {
  static const auto kCornerSigns = corner_signs<Dim>();
  const Index n = particles.size();
  v.corners.resize(static_cast<std::size_t>(n));
  v.checker.resize(static_cast<std::size_t>(n));
  v.stripes_horizontal.resize(static_cast<std::size_t>(n));
  v.stripes_vertical.resize(static_cast<std::size_t>(n));
  parallel_for(n, [&](Index p) {
    const auto s = static_cast<std::size_t>(p);
    const Mat<Dim> F = particles.grid_F(s);
    const Vec<Dim>& half = particles.half_size0[s];
    for (std::size_t c = 0; c < kCornerSigns.size(); ++c)
      v.corners[s][c] = particles.x[s] + F * kCornerSigns[c].cwiseProduct(half);
    // Pattern squares are counted from the grid origin; floor keeps the parity continuous
    // across negative coordinates.
    const Vec<Dim> square = ((particles.x0[s] - pattern_origin) / pattern_size).array().floor();
    std::int64_t sum = 0;
    for (int d = 0; d < Dim; ++d)
      sum += static_cast<std::int64_t>(square[d]);
    const auto ix = static_cast<std::int64_t>(square[0]);
    const auto iy = static_cast<std::int64_t>(square[1]);
    v.checker[s] = static_cast<std::int32_t>((sum % 2 + 2) % 2);
    v.stripes_horizontal[s] = static_cast<std::int32_t>((iy % 2 + 2) % 2);
    v.stripes_vertical[s] = static_cast<std::int32_t>((ix % 2 + 2) % 2);
  });
}

template void update_voxels<2>(const Particles<2>&, const Vec2&, double, Voxels<2>&);
template void update_voxels<3>(const Particles<3>&, const Vec3&, double, Voxels<3>&);

} // namespace talus
