// Deformed voxels and colour patterns (include/talus/post/voxels.hpp).
#include "talus/post/voxels.hpp"

#include "talus/core/parallel.hpp"

#include <cmath>

namespace talus {

void update_voxels(const Particles<2>& particles, const Vec2& pattern_origin, double pattern_size,
                   Voxels& v) {
  // Corner offsets X_c - X_p in units of the half-sizes, counter-clockwise.
  static const std::array<Vec2, 4> kCornerSigns = {Vec2(-1, -1), Vec2(1, -1), Vec2(1, 1),
                                                   Vec2(-1, 1)};
  const Index n = particles.size();
  v.corners.resize(static_cast<std::size_t>(n));
  v.checker.resize(static_cast<std::size_t>(n));
  v.stripes_horizontal.resize(static_cast<std::size_t>(n));
  v.stripes_vertical.resize(static_cast<std::size_t>(n));
  parallel_for(n, [&](Index p) {
    const auto s = static_cast<std::size_t>(p);
    const Mat2 F = particles.grid_F(s);
    const Vec2& half = particles.half_size0[s];
    for (std::size_t c = 0; c < 4; ++c)
      v.corners[s][c] = particles.x[s] + F * kCornerSigns[c].cwiseProduct(half);
    // Pattern squares are counted from the grid origin; floor keeps the parity continuous
    // across negative coordinates.
    const Vec2 square = ((particles.x0[s] - pattern_origin) / pattern_size).array().floor();
    const auto ix = static_cast<std::int64_t>(square.x());
    const auto iy = static_cast<std::int64_t>(square.y());
    v.checker[s] = static_cast<std::int32_t>(((ix + iy) % 2 + 2) % 2);
    v.stripes_horizontal[s] = static_cast<std::int32_t>((iy % 2 + 2) % 2);
    v.stripes_vertical[s] = static_cast<std::int32_t>((ix % 2 + 2) % 2);
  });
}

} // namespace talus
