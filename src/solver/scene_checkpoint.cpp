// The evolving part of a Scene in a checkpoint (include/talus/solver/scene_checkpoint.hpp).
// Entry names: particles/<field>, materials/<index>/history, surface_loads/<field>, probes.
#include "talus/solver/scene_checkpoint.hpp"

#include <fmt/format.h>
#include <stdexcept>

namespace talus {

namespace {

/// Fixed-size Eigen values (vectors, matrices) flattened column by column.
template <class T> std::vector<double> flatten(const Array<T>& values) {
  constexpr int n = T::SizeAtCompileTime;
  std::vector<double> out(values.size() * n);
  for (std::size_t i = 0; i < values.size(); ++i)
    std::copy(values[i].data(), values[i].data() + n, out.begin() + static_cast<long>(i * n));
  return out;
}

template <class T>
void unflatten(const CheckpointReader& in, const std::string& name, std::size_t count,
               Array<T>& values) {
  constexpr int n = T::SizeAtCompileTime;
  const std::vector<double> flat = in.doubles(name);
  if (flat.size() != count * n)
    throw std::runtime_error(fmt::format("checkpoint '{}': '{}' holds {} numbers, not {} x {}",
                                         in.file().string(), name, flat.size(), count, n));
  values.resize(count);
  for (std::size_t i = 0; i < count; ++i)
    values[i] = Eigen::Map<const T>(flat.data() + i * n);
}

template <class T> std::vector<std::int64_t> widen(const Array<T>& values) {
  return {values.begin(), values.end()};
}

template <class T>
void narrow(const CheckpointReader& in, const std::string& name, std::size_t count,
            Array<T>& values) {
  const std::vector<std::int64_t> wide = in.integers(name);
  if (wide.size() != count)
    throw std::runtime_error(fmt::format("checkpoint '{}': '{}' holds {} values, not {}",
                                         in.file().string(), name, wide.size(), count));
  values.assign(wide.begin(), wide.end());
}

/// An optional particle block: stored when allocated, empty when the checkpoint has none.
template <class T>
void save_optional(CheckpointWriter& out, const std::string& name, const Array<T>& values) {
  if (!values.empty())
    out.put(name, flatten(values));
}
template <class T>
void restore_optional(const CheckpointReader& in, const std::string& name, std::size_t count,
                      Array<T>& values) {
  values.clear();
  if (in.has(name))
    unflatten(in, name, count, values);
}

} // namespace

template <int Dim> void save_scene_state(const Scene<Dim>& scene, CheckpointWriter& out) {
  const Particles<Dim>& P = scene.particles;
  out.put_integer("particles/count", P.size());
  out.put("particles/x", flatten(P.x));
  out.put("particles/v", flatten(P.v));
  out.put("particles/mass", P.mass);
  out.put("particles/volume0", P.volume0);
  out.put("particles/volume", P.volume);
  out.put("particles/F", flatten(P.F));
  out.put("particles/stress", flatten(P.stress));
  out.put("particles/half_size0", flatten(P.half_size0));
  out.put("particles/x0", flatten(P.x0));
  out.put("particles/material", widen(P.material));
  out.put("particles/body", widen(P.body));
  out.put("particles/external_force", flatten(P.external_force));
  save_optional(out, "particles/affine_velocity", P.affine_velocity);
  save_optional(out, "particles/acceleration", P.acceleration);
  save_optional(out, "particles/split_origin_inverse", P.split_origin_inverse);
  if (!P.split_generation.empty())
    out.put("particles/split_generation", widen(P.split_generation));

  out.put_integer("materials/count", static_cast<std::int64_t>(scene.materials.size()));
  for (std::size_t m = 0; m < scene.materials.size(); ++m)
    out.put(fmt::format("materials/{}/history", m), scene.materials[m]->history());

  Array<Vec<Dim>> offset, force;
  std::vector<std::int64_t> particle, constant;
  for (const SurfaceLoad<Dim>& load : scene.surface_loads) {
    particle.push_back(load.particle);
    offset.push_back(load.offset);
    force.push_back(load.force);
    constant.push_back(load.constant ? 1 : 0);
  }
  out.put("surface_loads/particle", particle);
  out.put("surface_loads/offset", flatten(offset));
  out.put("surface_loads/force", flatten(force));
  out.put("surface_loads/constant", constant);
  out.put("probes",
          std::vector<std::int64_t>(scene.probe_particles.begin(), scene.probe_particles.end()));
}

template <int Dim> void restore_scene_state(const CheckpointReader& in, Scene<Dim>& scene) {
  const auto n = static_cast<std::size_t>(in.integer("particles/count"));
  Particles<Dim>& P = scene.particles;
  unflatten(in, "particles/x", n, P.x);
  unflatten(in, "particles/v", n, P.v);
  P.mass = in.doubles("particles/mass");
  P.volume0 = in.doubles("particles/volume0");
  P.volume = in.doubles("particles/volume");
  if (P.mass.size() != n || P.volume0.size() != n || P.volume.size() != n)
    throw std::runtime_error(
        fmt::format("checkpoint '{}': particle arrays of unequal length", in.file().string()));
  unflatten(in, "particles/F", n, P.F);
  unflatten(in, "particles/stress", n, P.stress);
  unflatten(in, "particles/half_size0", n, P.half_size0);
  unflatten(in, "particles/x0", n, P.x0);
  narrow(in, "particles/material", n, P.material);
  narrow(in, "particles/body", n, P.body);
  unflatten(in, "particles/external_force", n, P.external_force);
  restore_optional(in, "particles/affine_velocity", n, P.affine_velocity);
  restore_optional(in, "particles/acceleration", n, P.acceleration);
  restore_optional(in, "particles/split_origin_inverse", n, P.split_origin_inverse);
  P.split_generation.clear();
  if (in.has("particles/split_generation"))
    narrow(in, "particles/split_generation", n, P.split_generation);

  if (static_cast<std::size_t>(in.integer("materials/count")) != scene.materials.size())
    throw std::runtime_error(fmt::format("checkpoint '{}' has {} materials, the case {}",
                                         in.file().string(), in.integer("materials/count"),
                                         scene.materials.size()));
  scene.particles_of_material.assign(scene.materials.size(), {});
  for (std::size_t p = 0; p < n; ++p) {
    const auto m = static_cast<std::size_t>(P.material[p]);
    if (m >= scene.materials.size())
      throw std::runtime_error(
          fmt::format("checkpoint '{}': point {} has material {}", in.file().string(), p, m));
    scene.particles_of_material[m].push_back(static_cast<Index>(p));
  }
  for (std::size_t m = 0; m < scene.materials.size(); ++m)
    scene.materials[m]->restore_history(in.doubles(fmt::format("materials/{}/history", m)));

  const std::vector<std::int64_t> particle = in.integers("surface_loads/particle");
  const std::vector<std::int64_t> constant = in.integers("surface_loads/constant");
  Array<Vec<Dim>> offset, force;
  unflatten(in, "surface_loads/offset", particle.size(), offset);
  unflatten(in, "surface_loads/force", particle.size(), force);
  scene.surface_loads.resize(particle.size());
  for (std::size_t k = 0; k < particle.size(); ++k)
    scene.surface_loads[k] = {particle[k], offset[k], force[k], constant.at(k) != 0};
  const std::vector<std::int64_t> probes = in.integers("probes");
  if (probes.size() != scene.probe_particles.size())
    throw std::runtime_error(fmt::format("checkpoint '{}' has {} probes, the case {}",
                                         in.file().string(), probes.size(),
                                         scene.probe_particles.size()));
  scene.probe_particles.assign(probes.begin(), probes.end());
}

template void save_scene_state<2>(const Scene<2>&, CheckpointWriter&);
template void save_scene_state<3>(const Scene<3>&, CheckpointWriter&);
template void restore_scene_state<2>(const CheckpointReader&, Scene<2>&);
template void restore_scene_state<3>(const CheckpointReader&, Scene<3>&);

} // namespace talus
