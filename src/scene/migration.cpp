// Points moving between ranks (include/talus/scene/migration.hpp). A message to one rank:
//   header: optional-field mask, then per material the history values per point
//   per point: every particle array's value (for_each_field order), each material's history
//              row, its tractions (count, then offset, force, constant) and its probes (count,
//              then the probes' indices)
#include "talus/scene/migration.hpp"

#include "talus/core/parallel.hpp"

#include <algorithm>
#include <cstring>
#include <iterator>
#include <numeric>
#include <optional>
#include <stdexcept>

namespace talus {

namespace {

using Bytes = std::vector<std::byte>;

/// Fixed-size Eigen values travel as their coefficients.
template <class T> constexpr bool kEigen = requires {
  T::SizeAtCompileTime;
};
template <class T> constexpr std::size_t bytes_of() {
  if constexpr (kEigen<T>)
    return sizeof(double) * T::SizeAtCompileTime;
  else
    return sizeof(T);
}

template <class T> void put(Bytes& out, const T& value) {
  if constexpr (kEigen<T>) {
    const auto* b = reinterpret_cast<const std::byte*>(value.data());
    out.insert(out.end(), b, b + sizeof(double) * T::SizeAtCompileTime);
  } else {
    static_assert(std::is_trivially_copyable_v<T>);
    const auto* b = reinterpret_cast<const std::byte*>(&value);
    out.insert(out.end(), b, b + sizeof(T));
  }
}

class Cursor {
public:
  explicit Cursor(const Bytes& in) : in_(in) {}
  template <class T> T get() {
    T value;
    constexpr std::size_t bytes = bytes_of<T>();
    if (at_ + bytes > in_.size())
      throw std::logic_error("point message shorter than its contents");
    if constexpr (kEigen<T>)
      std::memcpy(value.data(), in_.data() + at_, bytes);
    else
      std::memcpy(&value, in_.data() + at_, bytes);
    at_ += bytes;
    return value;
  }
  bool done() const { return at_ == in_.size(); }

private:
  const Bytes& in_;
  std::size_t at_ = 0;
};

/// a <- (a[order[0]], a[order[1]], ...).
template <class A> void permute(A& a, const std::vector<std::size_t>& order) {
  A out(order.size());
  for (std::size_t i = 0; i < order.size(); ++i)
    out[i] = a[order[i]];
  a.swap(out);
}

/// Which optional particle blocks are allocated, one bit each in for_each_possible_field order.
template <int Dim> std::uint32_t optional_mask(const Particles<Dim>& P) {
  std::uint32_t mask = 0;
  int bit = 0;
  P.for_each_possible_field([&](const char* name, const auto& a, const auto&) {
    if (Particles<Dim>::optional_field(name)) {
      if (!a.empty())
        mask |= 1u << bit;
      ++bit;
    }
  });
  return mask;
}

/// What a rank adds to its points before keeping some: the received points' history rows and
/// tractions, appended after its own.
struct Incoming {
  std::vector<std::vector<double>> history; ///< per material, rows of the received points
  std::vector<std::size_t> history_width;   ///< per material: values per point (0: none)
};

template <int Dim> class PointPacker {
public:
  explicit PointPacker(Scene<Dim>& scene) : scene_(scene) {
    const auto n = static_cast<std::size_t>(scene.particles.size());
    for (const auto& m : scene.materials) {
      history_.push_back(m->history());
      const std::size_t values = history_.back().size();
      if (n > 0 && values % n != 0)
        throw std::logic_error("a material's history does not match the points");
      width_.push_back(n ? values / n : 0);
    }
    // The tractions by point (keep_points leaves them in point order; a scene as built may
    // list them otherwise).
    load_order_.resize(scene.surface_loads.size());
    std::iota(load_order_.begin(), load_order_.end(), std::size_t{0});
    std::stable_sort(load_order_.begin(), load_order_.end(), [&](std::size_t a, std::size_t b) {
      return scene.surface_loads[a].particle < scene.surface_loads[b].particle;
    });
  }

  /// The header of a message from this rank.
  void header(Bytes& out) {
    put(out, optional_mask(scene_.particles));
    put(out, static_cast<std::uint32_t>(width_.size()));
    for (const std::size_t w : width_)
      put(out, static_cast<std::uint64_t>(w));
  }

  void point(Bytes& out, std::size_t p) {
    scene_.particles.for_each_field(
        [&](const char*, const auto& a, const auto&) { put(out, a[p]); });
    for (std::size_t m = 0; m < width_.size(); ++m)
      for (std::size_t i = 0; i < width_[m]; ++i)
        put(out, history_[m][p * width_[m] + i]);
    const auto& loads = scene_.surface_loads;
    const auto [first, last] =
        std::equal_range(load_order_.begin(), load_order_.end(), static_cast<Index>(p),
                         [&](const auto& a, const auto& b) {
                           return particle_of(loads, a) < particle_of(loads, b);
                         });
    put(out, static_cast<std::uint32_t>(last - first));
    for (auto k = first; k != last; ++k) {
      const SurfaceLoad<Dim>& l = loads[*k];
      put(out, l.offset);
      put(out, l.force);
      put(out, static_cast<std::uint8_t>(l.constant));
    }
    std::vector<std::uint32_t> probes; // a handful in a scene: a scan
    for (std::size_t k = 0; k < scene_.probe_particles.size(); ++k)
      if (scene_.probe_particles[k] == static_cast<Index>(p))
        probes.push_back(static_cast<std::uint32_t>(k));
    put(out, static_cast<std::uint32_t>(probes.size()));
    for (const std::uint32_t k : probes)
      put(out, k);
  }

  std::vector<std::vector<double>>& history() { return history_; }
  std::vector<std::size_t>& width() { return width_; }

private:
  Scene<Dim>& scene_;
  std::vector<std::vector<double>> history_; ///< per material, as Material::history()
  std::vector<std::size_t> width_;
  std::vector<std::size_t> load_order_; ///< indices of the tractions, by point

  // equal_range compares load indices with a point index: the point of either.
  static Index particle_of(const std::vector<SurfaceLoad<Dim>>& loads, std::size_t k) {
    return loads[k].particle;
  }
  static Index particle_of(const std::vector<SurfaceLoad<Dim>>&, Index p) { return p; }
};

/// Appends the points of one message to the scene's arrays (and their history rows to
/// `history`); returns how many.
template <int Dim>
Index unpack(const Bytes& message, Scene<Dim>& scene, std::vector<std::vector<double>>& history,
             std::vector<std::size_t>& width) {
  if (message.empty())
    return 0;
  Particles<Dim>& P = scene.particles;
  Cursor in(message);
  const auto mask = in.get<std::uint32_t>();
  if (P.size() > 0 && mask != optional_mask(P))
    throw std::logic_error("ranks disagree on the points' optional arrays");
  const auto materials = in.get<std::uint32_t>();
  if (materials != scene.materials.size())
    throw std::logic_error("ranks disagree on the materials");
  for (std::size_t m = 0; m < materials; ++m) {
    const auto w = static_cast<std::size_t>(in.get<std::uint64_t>());
    if (width[m] != 0 && w != width[m] && P.size() > 0)
      throw std::logic_error("ranks disagree on a material's history");
    width[m] = w;
  }
  Index count = 0;
  while (!in.done()) {
    const auto p = static_cast<Index>(P.size());
    int bit = 0;
    P.for_each_possible_field([&](const char* name, auto& a, const auto&) {
      if (Particles<Dim>::optional_field(name) && !(mask & (1u << bit++)))
        return;
      a.push_back(in.get<typename std::decay_t<decltype(a)>::value_type>());
    });
    for (std::size_t m = 0; m < materials; ++m)
      for (std::size_t i = 0; i < width[m]; ++i)
        history[m].push_back(in.get<double>());
    const auto loads = in.get<std::uint32_t>();
    for (std::uint32_t k = 0; k < loads; ++k) {
      SurfaceLoad<Dim> l;
      l.particle = p;
      l.offset = in.get<Vec<Dim>>();
      l.force = in.get<Vec<Dim>>();
      l.constant = in.get<std::uint8_t>() != 0;
      scene.surface_loads.push_back(l);
    }
    const auto probes = in.get<std::uint32_t>();
    for (std::uint32_t k = 0; k < probes; ++k)
      scene.probe_particles.at(in.get<std::uint32_t>()) = p;
    ++count;
  }
  return count;
}

/// Keeps the points with keep[p] (the received ones, appended after the rank's own, are all
/// kept), in ascending global id, and renumbers the history, batches, tractions and probes.
template <int Dim>
void keep_points(Scene<Dim>& scene, const std::vector<char>& keep,
                 std::vector<std::vector<double>>& history, const std::vector<std::size_t>& width) {
  Particles<Dim>& P = scene.particles;
  const auto n = static_cast<std::size_t>(P.size());
  // The rank's own points ascend already; the received ones are sorted, then merged in.
  std::vector<std::size_t> own, received, order;
  for (std::size_t p = 0; p < n; ++p)
    if (p >= keep.size())
      received.push_back(p);
    else if (keep[p])
      own.push_back(p);
  const auto by_id = [&](std::size_t a, std::size_t b) { return P.global_id[a] < P.global_id[b]; };
  std::sort(received.begin(), received.end(), by_id);
  order.reserve(own.size() + received.size());
  std::merge(own.begin(), own.end(), received.begin(), received.end(), std::back_inserter(order),
             by_id);
  P.for_each_field([&](const char*, auto& a, const auto&) { permute(a, order); });
  std::vector<Index> renumbered(n, -1);
  for (std::size_t i = 0; i < order.size(); ++i)
    renumbered[order[i]] = static_cast<Index>(i);

  for (std::size_t m = 0; m < scene.materials.size(); ++m) {
    if (width[m] == 0)
      continue;
    std::vector<double> rows(order.size() * width[m]);
    for (std::size_t i = 0; i < order.size(); ++i)
      std::copy_n(history[m].begin() + static_cast<long>(order[i] * width[m]), width[m],
                  rows.begin() + static_cast<long>(i * width[m]));
    scene.materials[m]->restore_history(rows);
  }
  scene.particles_of_material.assign(scene.materials.size(), {});
  for (std::size_t p = 0; p < order.size(); ++p)
    scene.particles_of_material[static_cast<std::size_t>(P.material[p])].push_back(
        static_cast<Index>(p));
  std::vector<SurfaceLoad<Dim>> loads;
  for (SurfaceLoad<Dim> l : scene.surface_loads)
    if (const Index to = renumbered[static_cast<std::size_t>(l.particle)]; to >= 0) {
      l.particle = to;
      loads.push_back(l);
    }
  // The serial run's order: by point, then as listed.
  std::stable_sort(loads.begin(), loads.end(), [&](const auto& a, const auto& b) {
    return P.global_id[static_cast<std::size_t>(a.particle)] <
           P.global_id[static_cast<std::size_t>(b.particle)];
  });
  scene.surface_loads = std::move(loads);
  for (Index& p : scene.probe_particles)
    if (p >= 0)
      p = renumbered[static_cast<std::size_t>(p)];
}

} // namespace

template <int Dim> void distribute_scene(Scene<Dim>& scene, const Communicator& comm) {
  if (!comm.distributed())
    return;
  Particles<Dim>& P = scene.particles;
  const auto n = static_cast<std::size_t>(P.size());
  P.global_id.resize(n);
  std::iota(P.global_id.begin(), P.global_id.end(), std::int64_t{0});
  // Each rank hands the partitioner a block of the points: together they are all of them once.
  const auto first =
      n * static_cast<std::size_t>(comm.rank()) / static_cast<std::size_t>(comm.size());
  const auto last =
      n * static_cast<std::size_t>(comm.rank() + 1) / static_cast<std::size_t>(comm.size());
  auto decomposition = std::make_shared<Decomposition<Dim>>(Decomposition<Dim>::partition(
      comm, scene.grid, std::span<const Vec<Dim>>(P.x.data() + first, last - first)));
  std::vector<char> keep(n);
  for (std::size_t p = 0; p < n; ++p)
    keep[p] = decomposition->owner(P.x[p]) == comm.rank();
  PointPacker<Dim> packer(scene);
  keep_points(scene, keep, packer.history(), packer.width());
  scene.decomposition = std::move(decomposition);
}

template <int Dim> MigrationCount migrate_points(Scene<Dim>& scene) {
  MigrationCount count;
  if (!scene.distributed())
    return count;
  const Decomposition<Dim>& dec = *scene.decomposition;
  const Communicator& comm = dec.comm();
  Particles<Dim>& P = scene.particles;
  const auto n = static_cast<std::size_t>(P.size());
  std::vector<int> owner(n);
  parallel_for(P.size(), [&](Index p) {
    owner[static_cast<std::size_t>(p)] = dec.owner(P.x[static_cast<std::size_t>(p)]);
  });
  const bool leaving =
      std::any_of(owner.begin(), owner.end(), [&](int r) { return r != comm.rank(); });
  if (!comm.any(leaving))
    return count;
  PointPacker<Dim> packer(scene);
  std::vector<Bytes> to(static_cast<std::size_t>(comm.size()));
  std::vector<char> keep(n, 1);
  for (std::size_t p = 0; p < n; ++p) {
    if (owner[p] == comm.rank())
      continue;
    Bytes& out = to[static_cast<std::size_t>(owner[p])];
    if (out.empty())
      packer.header(out);
    packer.point(out, p);
    keep[p] = 0;
    ++count.sent;
  }
  const std::vector<Bytes> from = comm.all_to_all(to);
  for (const Bytes& message : from)
    count.received += unpack(message, scene, packer.history(), packer.width());
  keep_points(scene, keep, packer.history(), packer.width());
  return count;
}

template <int Dim> Index rebalance(Scene<Dim>& scene, double threshold) {
  const Communicator& comm = scene.decomposition->comm();
  const std::vector<std::int64_t> counts = comm.all_gather(std::int64_t{scene.particles.size()});
  const double total = static_cast<double>(std::accumulate(counts.begin(), counts.end(), 0LL));
  const double largest = static_cast<double>(*std::max_element(counts.begin(), counts.end()));
  if (!(largest > threshold * total / static_cast<double>(counts.size())))
    return -1;
  scene.decomposition = std::make_shared<Decomposition<Dim>>(Decomposition<Dim>::partition(
      comm, scene.grid, std::span<const Vec<Dim>>(scene.particles.x)));
  return migrate_points(scene).sent;
}

template <int Dim> void with_points_on_root(Scene<Dim>& scene, const std::function<void()>& work) {
  const auto owners = scene.decomposition;
  scene.decomposition = std::make_shared<Decomposition<Dim>>(
      Decomposition<Dim>::all_on(owners->comm(), scene.grid, 0));
  migrate_points(scene);
  std::optional<std::string> failure;
  try {
    work();
  } catch (const std::exception& e) {
    failure = e.what();
  }
  scene.decomposition = owners;
  migrate_points(scene);
  if (const auto first = owners->comm().first_message(failure))
    throw std::runtime_error(*first);
}

template <int Dim> Index name_new_points(Scene<Dim>& scene, Index first_new) {
  Particles<Dim>& P = scene.particles;
  const Communicator& comm = scene.decomposition->comm();
  const auto first = static_cast<std::size_t>(first_new);
  const std::int64_t before = comm.sum(std::int64_t{first_new});
  // The serial run appends a child per split parent, in the parents' order: the new points' ids
  // follow from where their parents' ids fall among all ranks' split parents.
  const std::span<const std::int64_t> parents(P.global_id.data() + first,
                                              P.global_id.size() - first);
  std::vector<std::int64_t> all = comm.all_gather_v(parents);
  std::sort(all.begin(), all.end());
  for (std::size_t p = first; p < P.global_id.size(); ++p)
    P.global_id[p] =
        before + (std::lower_bound(all.begin(), all.end(), P.global_id[p]) - all.begin());
  return static_cast<Index>(all.size());
}

template <int Dim>
Particles<Dim> gather_points(const Scene<Dim>& scene, std::vector<double>* plastic_strain) {
  const Particles<Dim>& P = scene.particles;
  const auto n = static_cast<std::size_t>(P.size());
  std::vector<double> strain;
  if (plastic_strain) {
    strain.assign(n, 0.0);
    for (std::size_t m = 0; m < scene.materials.size(); ++m)
      scene.materials[m]->plastic_strain(scene.particles_of_material[m], strain);
  }
  const Communicator& comm = scene.decomposition->comm();
  std::vector<Bytes> to(static_cast<std::size_t>(comm.size()));
  Bytes& out = to[0];
  if (n > 0) {
    put(out, optional_mask(P));
    for (std::size_t p = 0; p < n; ++p) {
      P.for_each_field([&](const char*, const auto& a, const auto&) { put(out, a[p]); });
      if (plastic_strain)
        put(out, strain[p]);
    }
  }
  const std::vector<Bytes> from = comm.all_to_all(to);
  Particles<Dim> all;
  std::vector<double> all_strain;
  for (const Bytes& message : from) {
    if (message.empty())
      continue;
    Cursor in(message);
    const auto mask = in.get<std::uint32_t>();
    while (!in.done()) {
      int bit = 0;
      all.for_each_possible_field([&](const char* name, auto& a, const auto&) {
        if (Particles<Dim>::optional_field(name) && !(mask & (1u << bit++)))
          return;
        a.push_back(in.get<typename std::decay_t<decltype(a)>::value_type>());
      });
      if (plastic_strain)
        all_strain.push_back(in.get<double>());
    }
  }
  // Global id order: the serial run's.
  std::vector<std::size_t> order(static_cast<std::size_t>(all.size()));
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return all.global_id[a] < all.global_id[b]; });
  all.for_each_field([&](const char*, auto& a, const auto&) { permute(a, order); });
  if (plastic_strain) {
    permute(all_strain, order);
    plastic_strain->swap(all_strain);
  }
  return all;
}

template void distribute_scene<2>(Scene<2>&, const Communicator&);
template void distribute_scene<3>(Scene<3>&, const Communicator&);
template MigrationCount migrate_points<2>(Scene<2>&);
template MigrationCount migrate_points<3>(Scene<3>&);
template void with_points_on_root<2>(Scene<2>&, const std::function<void()>&);
template void with_points_on_root<3>(Scene<3>&, const std::function<void()>&);
template Index rebalance<2>(Scene<2>&, double);
template Index rebalance<3>(Scene<3>&, double);
template Index name_new_points<2>(Scene<2>&, Index);
template Index name_new_points<3>(Scene<3>&, Index);
template Particles<2> gather_points<2>(const Scene<2>&, std::vector<double>*);
template Particles<3> gather_points<3>(const Scene<3>&, std::vector<double>*);

} // namespace talus
