#include "talus/material/plasticity/von_mises.hpp"

#include "talus/core/errors.hpp"

#include <cmath>
#include <fmt/format.h>

namespace talus {

VonMises::VonMises(const LameParameters& lame, double yield_stress, double hardening_modulus)
    : PlasticModel(lame), yield_stress_(yield_stress), hardening_(hardening_modulus) {
  if (!(yield_stress > 0.0) || !std::isfinite(yield_stress))
    throw InputError({"", 0, 0, "yield_stress"},
                     fmt::format("yield stress must be positive, got {:g}", yield_stress));
  if (!(hardening_modulus >= 0.0) || !std::isfinite(hardening_modulus))
    throw InputError(
        {"", 0, 0, "hardening_modulus"},
        fmt::format("hardening modulus must be non-negative, got {:g}", hardening_modulus));
}

double VonMises::yield_function(const Vec3& stress, double kappa) const {
  return std::sqrt(1.5) * deviator(stress).norm() - yield_stress(kappa);
}

PrincipalReturn VonMises::return_sorted(const Vec3& eps, double kappa) const {
  const double mu = lame().mu;
  const double bulk = lame().lambda + 2.0 * mu / 3.0;
  PrincipalReturn r;
  r.stress = elastic_stress(eps);
  r.kappa = kappa;
  r.elastic_strain = eps;
  r.tangent = elastic_stiffness();
  const Vec3 e = deviator(eps);
  const double q_trial = std::sqrt(6.0) * mu * e.norm(); // sqrt(3/2) |2 mu e|
  const double f = q_trial - yield_stress(kappa);
  if (f <= 0.0)
    return r;

  const double dk = f / (3.0 * mu + hardening_);
  const double shrink = 1.0 - 3.0 * mu * dk / q_trial; // s = shrink * s^tr
  const Vec3 n = e / e.norm();
  r.type = ReturnType::Surface;
  r.kappa = kappa + dk;
  r.elastic_strain = Vec3::Constant(eps.sum() / 3.0) + shrink * e;
  r.stress = Vec3::Constant(bulk * eps.sum()) + 2.0 * mu * shrink * e;
  r.tangent = bulk * Mat3::Constant(1.0) + 2.0 * mu * shrink * deviatoric_projector() +
              6.0 * mu * mu * (dk / q_trial - 1.0 / (3.0 * mu + hardening_)) * n * n.transpose();
  return r;
}

} // namespace talus
