#include "talus/material/plasticity/plastic_model.hpp"

#include "talus/core/errors.hpp"

#include <cmath>
#include <fmt/format.h>
#include <utility>

namespace talus {

const char* to_string(ReturnType type) {
  switch (type) {
  case ReturnType::Elastic:
    return "elastic";
  case ReturnType::Surface:
    return "surface";
  case ReturnType::CompressionEdge:
    return "compression edge";
  case ReturnType::ExtensionEdge:
    return "extension edge";
  case ReturnType::Apex:
    return "apex";
  }
  return "unknown";
}

LameParameters checked_lame_parameters(double youngs_modulus, double poisson_ratio) {
  if (!(youngs_modulus > 0.0) || !std::isfinite(youngs_modulus))
    throw InputError({"", 0, 0, "youngs_modulus"},
                     fmt::format("Young's modulus must be positive, got {:g}", youngs_modulus));
  if (!(poisson_ratio > -1.0 && poisson_ratio < 0.5))
    throw InputError({"", 0, 0, "poisson_ratio"},
                     fmt::format("Poisson's ratio must lie in (-1, 0.5), got {:g}", poisson_ratio));
  return LameParameters::from_young_poisson(youngs_modulus, poisson_ratio);
}

PlasticModel::PlasticModel(const LameParameters& lame) : lame_(lame) {
  const double bulk = lame.lambda + 2.0 * lame.mu / 3.0;
  if (!(lame.mu > 0.0) || !(bulk > 0.0) || !std::isfinite(lame.mu) || !std::isfinite(bulk))
    throw InputError({"", 0, 0, "poisson_ratio"},
                     fmt::format("elastic constants need a positive shear and bulk modulus, got "
                                 "mu = {:g}, K = {:g}",
                                 lame.mu, bulk));
}

PrincipalReturn PlasticModel::return_map(const Vec3& trial_elastic_strain, double kappa) const {
  const DescendingOrder order(trial_elastic_strain);
  PrincipalReturn r = return_sorted(order.sort(trial_elastic_strain), kappa);
  r.stress = order.unsort(r.stress);
  r.elastic_strain = order.unsort(r.elastic_strain);
  r.tangent = order.unsort(r.tangent);
  return r;
}

Vec3 PlasticModel::elastic_stress(const Vec3& strain) const {
  return Vec3::Constant(lame_.lambda * strain.sum()) + 2.0 * lame_.mu * strain;
}

Mat3 PlasticModel::elastic_stiffness() const {
  return Mat3::Constant(lame_.lambda) + 2.0 * lame_.mu * Mat3::Identity();
}

DescendingOrder::DescendingOrder(const Vec3& v) {
  // three compare-and-swaps sort three values
  auto before = [&](int a, int b) {
    if (v(order[a]) < v(order[b]))
      std::swap(order[a], order[b]);
  };
  before(0, 1);
  before(1, 2);
  before(0, 1);
}

Vec3 DescendingOrder::sort(const Vec3& v) const {
  return {v(order[0]), v(order[1]), v(order[2])};
}

Vec3 DescendingOrder::unsort(const Vec3& sorted) const {
  Vec3 v;
  for (int i = 0; i < 3; ++i)
    v(order[i]) = sorted(i);
  return v;
}

Mat3 DescendingOrder::unsort(const Mat3& sorted) const {
  Mat3 m;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      m(order[i], order[j]) = sorted(i, j);
  return m;
}

} // namespace talus
