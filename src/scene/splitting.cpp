#include "talus/scene/splitting.hpp"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

namespace talus {

template <int Dim> SplitMode split_mode(const Mat<Dim>& Fs, const SplitSpec& spec) {
  const auto diagonal = Fs.diagonal();
  if ((diagonal.array() > spec.alpha).any())
    return SplitMode::Stretch;
  if ((diagonal.array() < spec.beta).any())
    return SplitMode::Compression;
  for (int i = 0; i < Dim; ++i)
    for (int j = 0; j < Dim; ++j)
      if (i != j && std::abs(Fs(i, j)) > spec.gamma)
        return SplitMode::Shear;
  return SplitMode::None;
}

template <int Dim> int split_axis(const Mat<Dim>& F, const Vec<Dim>& half_size0) {
  int axis = 0;
  for (int d = 1; d < Dim; ++d)
    if (F.col(d).norm() * half_size0[d] > F.col(axis).norm() * half_size0[axis])
      axis = d;
  return axis;
}

bool splitting_requested(const CaseSpec& spec) {
  return std::any_of(spec.bodies.begin(), spec.bodies.end(),
                     [](const BodySpec& b) { return b.split.has_value(); });
}

template <int Dim> void enable_splitting(Scene<Dim>& scene) {
  if (!splitting_requested(scene.spec))
    return;
  auto& P = scene.particles;
  P.split_origin_inverse.assign(static_cast<std::size_t>(P.size()), Mat3::Identity());
  P.split_generation.assign(static_cast<std::size_t>(P.size()), 0);
}

template <int Dim> Index split_point(Particles<Dim>& P, Index p, int axis) {
  const Index q = P.append_copy(p);
  const auto a = static_cast<std::size_t>(p);
  const auto b = static_cast<std::size_t>(q);
  Vec<Dim> shift0 = Vec<Dim>::Zero();
  shift0[axis] = 0.5 * P.half_size0[a][axis];
  const Vec<Dim> shift = P.grid_F(a) * shift0;
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
// the cut (o_axis = 0) is shared, the fractions share_p and share_q of the force on the
// children at the same offset (halves; in axisymmetry each half's ring); a face normal to the
// cut belongs to the child on its side, at the child's half-width.
template <int Dim>
void move_surface_loads(std::vector<SurfaceLoad<Dim>>& loads, Index p, Index q, int axis,
                        double child_half, double share_p, double share_q) {
  const std::size_t count = loads.size();
  for (std::size_t k = 0; k < count; ++k) {
    SurfaceLoad<Dim>& load = loads[k];
    if (load.particle != p)
      continue;
    if (load.offset[axis] == 0.0) {
      SurfaceLoad<Dim> copy = load;
      load.force *= share_p;
      copy.force *= share_q;
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

template <int Dim> Index split_material_points(Scene<Dim>& scene) {
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
    const Mat3 F_split = P.F[s] * P.split_origin_inverse[s];
    if (split_mode<Dim>(F_split.template topLeftCorner<Dim, Dim>(), *split) == SplitMode::None)
      continue;
    const Mat<Dim> F = P.grid_F(s);
    const int axis = split_axis<Dim>(F, P.half_size0[s]);
    // A child's deformed edge across the cut: half the parent's, |F e_d| 2 h_d / 2.
    if (F.col(axis).norm() * P.half_size0[s][axis] < split->min_size)
      continue;
    splits.emplace_back(p, axis);
  }
  if (splits.empty())
    return 0;
  std::vector<Index> sources;
  sources.reserve(splits.size());
  const bool axisymmetric = scene.spec.geometry == Geometry::Axisymmetric;
  for (const auto& [p, axis] : splits) {
    const double radius = P.x[static_cast<std::size_t>(p)][0];
    const Index q = split_point(P, p, axis);
    sources.push_back(p);
    const auto s = static_cast<std::size_t>(p);
    double share_p = 0.5, share_q = 0.5;
    if (axisymmetric) {
      // Each half sweeps its own ring: mass and volume go with the child's radius (Pappus), so
      // the two rings hold the parent's exactly (the children sit at r -+ the same shift).
      share_p = 0.5 * P.x[s][0] / radius;
      share_q = 0.5 * P.x[static_cast<std::size_t>(q)][0] / radius;
      for (const auto& [c, share] :
           {std::pair{s, share_p}, std::pair{static_cast<std::size_t>(q), share_q}}) {
        P.mass[c] *= 2.0 * share;
        P.volume0[c] *= 2.0 * share;
        P.volume[c] *= 2.0 * share;
      }
    }
    scene.particles_of_material[static_cast<std::size_t>(P.material[s])].push_back(q);
    move_surface_loads<Dim>(scene.surface_loads, p, q, axis, P.half_size0[s][axis], share_p,
                            share_q);
  }
  for (const auto& material : scene.materials)
    material->append_copies(old_count, sources);
  return static_cast<Index>(splits.size());
}

template SplitMode split_mode<2>(const Mat2&, const SplitSpec&);
template SplitMode split_mode<3>(const Mat3&, const SplitSpec&);
template int split_axis<2>(const Mat2&, const Vec2&);
template int split_axis<3>(const Mat3&, const Vec3&);
template void enable_splitting<2>(Scene<2>&);
template void enable_splitting<3>(Scene<3>&);
template Index split_point<2>(Particles<2>&, Index, int);
template Index split_point<3>(Particles<3>&, Index, int);
template Index split_material_points<2>(Scene<2>&);
template Index split_material_points<3>(Scene<3>&);

} // namespace talus
