#include "talus/core/splitting.hpp"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

namespace talus {

SplitMode split_mode(const Mat2& Fs, const SplitSpec& spec) {
  if (Fs(0, 0) > spec.alpha || Fs(1, 1) > spec.alpha)
    return SplitMode::Stretch;
  if (Fs(0, 0) < spec.beta || Fs(1, 1) < spec.beta)
    return SplitMode::Compression;
  if (std::abs(Fs(0, 1)) > spec.gamma || std::abs(Fs(1, 0)) > spec.gamma)
    return SplitMode::Shear;
  return SplitMode::None;
}

int split_axis(const Mat2& F, const Vec2& half_size0) {
  return F.col(1).norm() * half_size0.y() > F.col(0).norm() * half_size0.x() ? 1 : 0;
}

bool splitting_requested(const CaseSpec& spec) {
  return std::any_of(spec.bodies.begin(), spec.bodies.end(),
                     [](const BodySpec& b) { return b.split.has_value(); });
}

void enable_splitting(Scene<2>& scene) {
  if (!splitting_requested(scene.spec))
    return;
  auto& P = scene.particles;
  P.split_origin_inverse.assign(static_cast<std::size_t>(P.size()), Mat2::Identity());
  P.split_generation.assign(static_cast<std::size_t>(P.size()), 0);
}

Index split_point(Particles<2>& P, Index p, int axis) {
  const Index q = P.append_copy(p);
  const auto a = static_cast<std::size_t>(p);
  const auto b = static_cast<std::size_t>(q);
  Vec2 shift0 = Vec2::Zero();
  shift0[axis] = 0.5 * P.half_size0[a][axis];
  const Vec2 shift = P.F[a] * shift0;
  P.x[a] -= shift;
  P.x[b] += shift;
  P.x0[a] -= shift0;
  P.x0[b] += shift0;
  for (const std::size_t c : {a, b}) {
    P.half_size0[c][axis] *= 0.5;
    P.mass[c] *= 0.5;
    P.volume0[c] *= 0.5;
    P.volume[c] *= 0.5;
    P.external_force[c] *= 0.5;
    if (!P.split_origin_inverse.empty())
      P.split_origin_inverse[c] = P.F[c].inverse();
    if (!P.split_generation.empty())
      ++P.split_generation[c];
  }
  return q;
}

namespace {

// A traction on the face of split point p (reference offset o from its centre): a face across
// the cut (o_axis = 0) is shared, half the force on each child at the same offset; a face
// normal to the cut belongs to the child on its side, at the child's half-width.
void move_surface_loads(std::vector<SurfaceLoad>& loads, Index p, Index q, int axis,
                        double child_half) {
  const std::size_t count = loads.size();
  for (std::size_t k = 0; k < count; ++k) {
    SurfaceLoad& load = loads[k];
    if (load.particle != p)
      continue;
    if (load.offset[axis] == 0.0) {
      load.force *= 0.5;
      SurfaceLoad copy = load;
      copy.particle = q;
      loads.push_back(copy);
      continue;
    }
    if (load.offset[axis] > 0.0)
      load.particle = q;
    load.offset[axis] = std::copysign(child_half, load.offset[axis]);
  }
}

} // namespace

Index split_material_points(Scene<2>& scene) {
  auto& P = scene.particles;
  if (P.split_generation.empty())
    return 0;
  const Index old_count = P.size();
  std::vector<std::pair<Index, int>> splits;
  for (Index p = 0; p < old_count; ++p) {
    const auto s = static_cast<std::size_t>(p);
    const auto& split = scene.spec.bodies[static_cast<std::size_t>(P.body[s])].split;
    if (!split || P.split_generation[s] >= split->max_generations)
      continue;
    if (split_mode(P.F[s] * P.split_origin_inverse[s], *split) == SplitMode::None)
      continue;
    const int axis = split_axis(P.F[s], P.half_size0[s]);
    // A child's deformed edge across the cut: half the parent's, |F e_d| 2 h_d / 2.
    if (P.F[s].col(axis).norm() * P.half_size0[s][axis] < split->min_size)
      continue;
    splits.emplace_back(p, axis);
  }
  if (splits.empty())
    return 0;
  std::vector<Index> sources;
  sources.reserve(splits.size());
  for (const auto& [p, axis] : splits) {
    const Index q = split_point(P, p, axis);
    sources.push_back(p);
    const auto s = static_cast<std::size_t>(p);
    scene.particles_of_material[static_cast<std::size_t>(P.material[s])].push_back(q);
    move_surface_loads(scene.surface_loads, p, q, axis, P.half_size0[s][axis]);
  }
  for (const auto& material : scene.materials)
    material->append_copies(old_count, sources);
  return static_cast<Index>(splits.size());
}

} // namespace talus
