#include "talus/solver/state_guard.hpp"

#include "talus/core/parallel.hpp"

#include <cmath>
#include <fmt/format.h>

namespace talus {

namespace {

/// The first component that is not finite, if any.
template <class Derived>
std::optional<double> non_finite_component(const Eigen::MatrixBase<Derived>& m) {
  for (Eigen::Index i = 0; i < m.size(); ++i)
    if (!std::isfinite(m.derived().coeff(i)))
      return m.derived().coeff(i);
  return std::nullopt;
}

template <int Dim>
StateViolation particle_violation(const Particles<Dim>& P, std::size_t s, const char* field,
                                  double value, const char* condition) {
  // A distributed run names the point as the serial run would.
  const Index name = P.global_id.empty() ? static_cast<Index>(s) : P.global_id[s];
  return StateViolation{field, false, name, padded<Dim>(P.x0[s]), Dim, value, condition};
}

} // namespace

std::string StateViolation::describe() const {
  const std::string at =
      dimension == 3 ? fmt::format("({:g}, {:g}, {:g})", position.x(), position.y(), position.z())
                     : fmt::format("({:g}, {:g})", position.x(), position.y());
  const std::string where = on_node ? fmt::format("grid node {} at {}", index, at)
                                    : fmt::format("particle {} (initial position {})", index, at);
  return fmt::format("{} = {:g} {} at {}", field, value, condition, where);
}

namespace {

/// Point s's first violation, in the order the step computes the fields, so the report names
/// the earliest symptom.
template <int Dim>
std::optional<StateViolation> particle_violation_at(const Particles<Dim>& P, std::size_t s) {
  constexpr const char* kNotFinite = "is not finite";
  if (const auto bad = non_finite_component(P.v[s]))
    return particle_violation(P, s, "velocity", *bad, kNotFinite);
  if (const auto bad = non_finite_component(P.x[s]))
    return particle_violation(P, s, "position", *bad, kNotFinite);
  if (const auto bad = non_finite_component(P.F[s]))
    return particle_violation(P, s, "F", *bad, kNotFinite);
  const double J = P.F[s].determinant();
  if (!(J > 0.0))
    return particle_violation(P, s, "det F", J, "<= 0 (inverted or collapsed point)");
  if (J < kCollapsedVolumeRatio)
    return particle_violation(P, s, "det F", J,
                              "< 1e-4 (collapsed point: under a hundredth of its spacing)");
  if (const auto bad = non_finite_component(P.stress[s]))
    return particle_violation(P, s, "stress", *bad, kNotFinite);
  return std::nullopt;
}

/// The same tests as particle_violation_at without building a report: the per-step pass.
template <int Dim> bool particle_is_bad(const Particles<Dim>& P, std::size_t s) {
  const double J = P.F[s].determinant();
  return !P.v[s].allFinite() || !P.x[s].allFinite() || !P.F[s].allFinite() ||
         !(J >= kCollapsedVolumeRatio) || !P.stress[s].allFinite();
}

} // namespace

template <int Dim> std::optional<StateViolation> find_particle_violation(const Particles<Dim>& P) {
  const Index first = parallel_find_first(
      P.size(), [&](Index p) { return particle_is_bad(P, static_cast<std::size_t>(p)); });
  if (first < 0)
    return std::nullopt;
  return particle_violation_at(P, static_cast<std::size_t>(first));
}

template <int Dim>
std::optional<StateViolation> find_node_violation(const ActiveNodes<Dim>& nodes,
                                                  std::span<const Vec<Dim>> field,
                                                  const char* field_name) {
  const Index n = parallel_find_first(
      nodes.size(), [&](Index k) { return !field[static_cast<std::size_t>(k)].allFinite(); });
  if (n < 0)
    return std::nullopt;
  return StateViolation{field_name,
                        true,
                        nodes.lattice_id(n),
                        padded<Dim>(nodes.position(n)),
                        Dim,
                        *non_finite_component(field[static_cast<std::size_t>(n)]),
                        "is not finite"};
}

template <int Dim>
std::optional<StateViolation> find_courant_violation(const Scene<Dim>& scene, double dt) {
  const auto& P = scene.particles;
  const double h = scene.grid.cell_size();
  double worst = 1.0;
  std::optional<StateViolation> found;
  for (std::size_t s = 0; s < P.x.size(); ++s) {
    const double c = scene.materials[static_cast<std::size_t>(P.material[s])]->wave_speed();
    const double courant = dt * (c + P.v[s].norm()) / h;
    if (courant > worst) {
      worst = courant;
      found = particle_violation(P, s, "Courant number dt (c_p + |v|) / h", courant,
                                 "exceeds 1 (the time step is above the stability limit)");
    }
  }
  return found;
}

#define TALUS_INSTANTIATE(Dim)                                                                     \
  template std::optional<StateViolation> find_particle_violation<Dim>(const Particles<Dim>&);      \
  template std::optional<StateViolation> find_node_violation<Dim>(                                 \
      const ActiveNodes<Dim>&, std::span<const Vec<Dim>>, const char*);                            \
  template std::optional<StateViolation> find_courant_violation<Dim>(const Scene<Dim>&, double);
TALUS_INSTANTIATE(2)
TALUS_INSTANTIATE(3)
#undef TALUS_INSTANTIATE

} // namespace talus
