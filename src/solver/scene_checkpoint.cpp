// The evolving part of a Scene in a checkpoint (include/talus/solver/scene_checkpoint.hpp).
// Entry names: particles/<field>, materials/<index>/history, surface_loads/<field>, probes.
#include "talus/solver/scene_checkpoint.hpp"

#include <fmt/format.h>
#include <stdexcept>
#include <string_view>
#include <type_traits>

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

/// One per-point array under its name: numbers as they are, integers widened, Eigen values
/// flattened.
template <class T>
void put_field(CheckpointWriter& out, const std::string& name, const Array<T>& a) {
  if constexpr (std::is_same_v<T, double>)
    out.put(name, a);
  else if constexpr (std::is_integral_v<T>)
    out.put(name, widen(a));
  else
    out.put(name, flatten(a));
}
template <class T>
void read_field(const CheckpointReader& in, const std::string& name, std::size_t count,
                Array<T>& a) {
  if constexpr (std::is_same_v<T, double>) {
    a = in.doubles(name);
    if (a.size() != count)
      throw std::runtime_error(fmt::format("checkpoint '{}': '{}' holds {} values, not {}",
                                           in.file().string(), name, a.size(), count));
  } else if constexpr (std::is_integral_v<T>) {
    narrow(in, name, count, a);
  } else {
    unflatten(in, name, count, a);
  }
}

} // namespace

template <int Dim> void save_scene_state(const Scene<Dim>& scene, CheckpointWriter& out) {
  const Particles<Dim>& P = scene.particles;
  out.put_integer("particles/count", P.size());
  // A distributed run saves its points gathered in the serial order (with_points_on_root), so
  // their global ids are their indices: the ranks of a resumed run number them anew.
  P.for_each_field([&](const char* name, const auto& a, const auto&) {
    if (std::string_view(name) != "global_id")
      put_field(out, fmt::format("particles/{}", name), a);
  });

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
  // Every array the checkpoint holds; an optional block it does not hold stays unallocated (a
  // required one it lacks is refused by the reader, naming it).
  P.for_each_possible_field([&](const char* name, auto& a, const auto&) {
    const std::string entry = fmt::format("particles/{}", name);
    a.clear();
    if (in.has(entry) || !Particles<Dim>::optional_field(name))
      read_field(in, entry, n, a);
  });

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
