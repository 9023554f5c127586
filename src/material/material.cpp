#include "talus/material/material.hpp"

#include "talus/core/errors.hpp"
#include "talus/core/parallel.hpp"

#include <cmath>
#include <fmt/format.h>

namespace talus {

double Material::wave_speed() const {
  return std::sqrt(lame_.p_wave_modulus() / density_);
}

Mat3 LinearElastic::stress(const Mat3& F) const {
  const Mat3 eps = 0.5 * (F + F.transpose()) - Mat3::Identity();
  return lame().lambda * eps.trace() * Mat3::Identity() + 2.0 * lame().mu * eps;
}

void LinearElastic::update_stress(std::span<const Index> ids, std::span<const Mat2> F,
                                  std::span<Mat3> stress_out) const {
  parallel_for(static_cast<Index>(ids.size()), [&](Index k) {
    const auto p = static_cast<std::size_t>(ids[static_cast<std::size_t>(k)]);
    stress_out[p] = stress(embed_plane_strain(F[p]));
  });
}

double LinearElastic::energy_density(const Mat3& F) const {
  const Mat3 eps = 0.5 * (F + F.transpose()) - Mat3::Identity();
  return 0.5 * lame().lambda * eps.trace() * eps.trace() + lame().mu * eps.squaredNorm();
}

Mat3 NeoHookean::stress(const Mat3& F) const {
  const double J = F.determinant();
  if (!(J > 0.0))
    throw NumericalError(
        fmt::format("neo-Hookean material '{}': det F = {:g} is not positive", name(), J));
  const Mat3 b = F * F.transpose();
  return (lame().mu / J) * (b - Mat3::Identity()) +
         (lame().lambda * std::log(J) / J) * Mat3::Identity();
}

void NeoHookean::update_stress(std::span<const Index> ids, std::span<const Mat2> F,
                               std::span<Mat3> stress_out) const {
  parallel_for(static_cast<Index>(ids.size()), [&](Index k) {
    const auto p = static_cast<std::size_t>(ids[static_cast<std::size_t>(k)]);
    stress_out[p] = stress(embed_plane_strain(F[p]));
  });
}

double NeoHookean::energy_density(const Mat3& F) const {
  const double J = F.determinant();
  const double lnJ = std::log(J);
  return 0.5 * lame().mu * ((F.transpose() * F).trace() - 3.0) - lame().mu * lnJ +
         0.5 * lame().lambda * lnJ * lnJ;
}

std::unique_ptr<Material> make_material(const MaterialSpec& spec) {
  const auto lame = LameParameters::from_young_poisson(spec.youngs_modulus, spec.poisson_ratio);
  switch (spec.model) {
  case MaterialModel::LinearElastic:
    return std::make_unique<LinearElastic>(spec.name, spec.density, lame);
  case MaterialModel::NeoHookean:
    return std::make_unique<NeoHookean>(spec.name, spec.density, lame);
  }
  throw std::logic_error("unknown material model");
}

} // namespace talus
