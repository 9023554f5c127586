#include "talus/material/plasticity/drucker_prager.hpp"

#include "talus/core/errors.hpp"

#include <cmath>
#include <fmt/format.h>

namespace talus {

namespace {

/// See mohr_coulomb.cpp: the local Newton stops at this fraction of the stress scale.
constexpr double kResidualTolerance = 1e-13;
constexpr int kMaxIterations = 50;

} // namespace

DruckerPragerMatch plane_strain_match(double cohesion, double friction, double dilation) {
  const double sp = std::sin(friction), cp = std::cos(friction), sg = std::sin(dilation);
  const double S = std::sqrt(9.0 + 3.0 * sg * sg);
  const double den = 3.0 + sp * sg;
  DruckerPragerMatch m;
  m.alpha = sp * S / (3.0 * den);
  m.k = cohesion * cp * S / den;
  m.alpha_flow = sg / S;
  m.dalpha_dphi = S * cp / (den * den);
  m.dk_dphi = -cohesion * S * (3.0 * sp + sg) / (den * den);
  m.dk_dc = cp * S / den;
  return m;
}

DruckerPrager::DruckerPrager(const LameParameters& lame,
                             const FrictionalStrengthParameters& strength)
    : PlasticModel(lame), strength_(strength) {}

DruckerPragerMatch DruckerPrager::coefficients(double kappa) const {
  const StrengthState s = strength_.at(kappa);
  return plane_strain_match(s.cohesion, s.friction, strength_.dilation());
}

double DruckerPrager::yield_function(const Vec3& stress, double kappa) const {
  const DruckerPragerMatch m = coefficients(kappa);
  return deviator(stress).norm() / std::sqrt(2.0) + m.alpha * stress.sum() - m.k;
}

PrincipalReturn DruckerPrager::return_sorted(const Vec3& eps, double kappa_n) const {
  const double mu = lame().mu;
  const double bulk = lame().lambda + 2.0 * mu / 3.0;
  const Vec3 trial = elastic_stress(eps);
  if (yield_function(trial, kappa_n) <= 0.0)
    return {trial, elastic_stiffness(), eps, kappa_n, ReturnType::Elastic};

  const Vec3 e = deviator(eps);
  const double rho = e.norm();
  const double sqrt_J2_trial = std::sqrt(2.0) * mu * rho;
  const double I1_trial = 3.0 * bulk * eps.sum();
  const double alpha_flow = coefficients(kappa_n).alpha_flow;
  PrincipalReturn out;
  if (rho > 0.0) {
    // cone: Newton on dg from the frozen-strength (perfectly plastic) solution
    DruckerPragerMatch m = coefficients(kappa_n);
    const double scale = std::abs(sqrt_J2_trial) + std::abs(m.alpha * I1_trial) + m.k;
    double dg = yield_function(trial, kappa_n) / (mu + 9.0 * bulk * m.alpha * alpha_flow);
    double kappa = kappa_n, I1 = I1_trial, drdg = 0;
    for (int it = 0;; ++it) {
      kappa = kappa_n + dg / std::sqrt(3.0);
      const StrengthState s = strength_.at(kappa);
      m = plane_strain_match(s.cohesion, s.friction, strength_.dilation());
      I1 = I1_trial - 9.0 * bulk * alpha_flow * dg;
      const double r = sqrt_J2_trial - mu * dg + m.alpha * I1 - m.k;
      const double dalpha = m.dalpha_dphi * s.friction_slope;
      const double dk = m.dk_dc * s.cohesion_slope + m.dk_dphi * s.friction_slope;
      drdg = -mu - 9.0 * bulk * m.alpha * alpha_flow + (dalpha * I1 - dk) / std::sqrt(3.0);
      if (std::abs(r) <= kResidualTolerance * scale)
        break;
      if (it == kMaxIterations || !std::isfinite(r))
        throw NumericalError(fmt::format("{}: local Newton for the cone return did not converge "
                                         "(yield residual {:g} after {} iterations)",
                                         name(), r, it));
      dg -= r / drdg;
    }
    if (sqrt_J2_trial - mu * dg >= 0.0) {
      const Vec3 n = e / rho;
      const Mat3 P = deviatoric_projector();
      const Vec3 ddg = -(std::sqrt(2.0) * mu * n + Vec3::Constant(3.0 * bulk * m.alpha)) / drdg;
      out.type = ReturnType::Surface;
      out.kappa = kappa;
      out.stress = Vec3::Constant(I1 / 3.0) + 2.0 * mu * e - std::sqrt(2.0) * mu * dg * n;
      out.elastic_strain = eps - dg * (n / std::sqrt(2.0) + Vec3::Constant(alpha_flow));
      out.tangent =
          bulk * Mat3::Constant(1.0) + 2.0 * mu * P -
          (std::sqrt(2.0) * mu * dg / rho) * (P - n * n.transpose()) -
          (Vec3::Constant(3.0 * bulk * alpha_flow) + std::sqrt(2.0) * mu * n) * ddg.transpose();
      return out;
    }
  }

  // apex: all deviatoric trial strain is plastic
  if (!strength_.frictional()) // alpha = 0 is a cylinder: the cone return is always valid
    throw NumericalError(fmt::format("{}: the cone return failed and phi = 0 has no apex", name()));
  out.type = ReturnType::Apex;
  out.kappa = kappa_n + std::sqrt(2.0 / 3.0) * rho;
  const StrengthState s = strength_.at(out.kappa);
  const double sp = std::sin(s.friction), cot = std::cos(s.friction) / sp;
  const double p = s.cohesion * cot;
  const double dp = s.cohesion_slope * cot - s.cohesion * s.friction_slope / (sp * sp);
  out.stress = Vec3::Constant(p);
  out.elastic_strain = Vec3::Constant(p / (3.0 * bulk));
  if (rho > 0.0)
    out.tangent = (std::sqrt(2.0 / 3.0) * dp / rho) * Vec3::Ones() * e.transpose();
  return out;
}

} // namespace talus
