#include "talus/material/plasticity/mohr_coulomb.hpp"

#include "talus/core/errors.hpp"

#include <array>
#include <cmath>
#include <fmt/format.h>

namespace talus {

namespace {

/// The plane (1 + s) sigma_hi - (1 - s) sigma_lo of the sorted sextant (hi < lo).
struct Plane {
  int hi, lo;
};

Vec3 plane_normal(const Plane& p, double sin_angle) {
  Vec3 v = Vec3::Zero();
  v(p.hi) = 1.0 + sin_angle;
  v(p.lo) = -(1.0 - sin_angle);
  return v;
}

/// The local Newton stops when every residual is below this fraction of the stress scale
/// |sigma^tr| + 2 c cos(phi): about 50 round-offs of the residual's own evaluation, so the
/// multipliers are exact to ~1e-13 relative, far below what the finite-difference checks see.
constexpr double kResidualTolerance = 1e-13;
constexpr int kMaxIterations = 50;

/// Return to the M planes `planes` (all active, f_i = 0): the main plane alone (M = 1) or an edge
/// (M = 2). Newton on the multipliers dg, started from the frozen-strength solution.
template <int M>
PrincipalReturn return_to_planes(const PlasticModel& model, const FrictionalStrength& strength,
                                 const std::array<Plane, M>& planes, const Vec3& eps,
                                 double kappa_n, ReturnType type) {
  using VecM = Eigen::Matrix<double, M, 1>;
  using MatM = Eigen::Matrix<double, M, M>;
  const Mat3 D = model.elastic_stiffness();
  const Vec3 sigma_trial = D * eps;
  const double sin_psi = std::sin(strength.dilation());
  Eigen::Matrix<double, 3, M> b, Db, dev_b;
  for (int i = 0; i < M; ++i) {
    b.col(i) = plane_normal(planes[static_cast<std::size_t>(i)], sin_psi);
    dev_b.col(i) = deviator(b.col(i));
  }
  Db = D * b;

  // yield planes a_i . sigma - k at kappa, with their kappa derivatives
  Eigen::Matrix<double, M, 3> A, dA;
  double k = 0, dk = 0;
  auto set_planes = [&](double kappa) {
    const StrengthState s = strength.at(kappa);
    const double sp = std::sin(s.friction), cp = std::cos(s.friction);
    for (int i = 0; i < M; ++i) {
      const Plane& p = planes[static_cast<std::size_t>(i)];
      A.row(i) = plane_normal(p, sp).transpose();
      dA.row(i).setZero();
      dA(i, p.hi) = dA(i, p.lo) = cp * s.friction_slope;
    }
    k = 2.0 * s.cohesion * cp;
    dk = 2.0 * (s.cohesion_slope * cp - s.cohesion * sp * s.friction_slope);
  };

  set_planes(kappa_n);
  const double scale = sigma_trial.cwiseAbs().maxCoeff() + k;
  VecM dg = (A * Db).inverse() * (A * sigma_trial - VecM::Constant(k));
  Vec3 sigma;
  double kappa = kappa_n;
  MatM J;
  for (int it = 0;; ++it) {
    // kappa = kappa_n + sqrt(2/3) |dev(b dg)| and its gradient in dg
    const Vec3 d = dev_b * dg;
    const double norm = d.norm();
    Eigen::Matrix<double, 1, M> dkappa;
    if (norm > 0.0)
      dkappa = std::sqrt(2.0 / 3.0) * (dev_b.transpose() * d).transpose() / norm;
    else // the derivative for dg -> 0+ (only the start of a vanishing step)
      dkappa = std::sqrt(2.0 / 3.0) * dev_b.colwise().norm();
    kappa = kappa_n + std::sqrt(2.0 / 3.0) * norm;
    set_planes(kappa);
    sigma = sigma_trial - Db * dg;
    const VecM r = A * sigma - VecM::Constant(k);
    J = -A * Db + (dA * sigma - VecM::Constant(dk)) * dkappa;
    if (r.cwiseAbs().maxCoeff() <= kResidualTolerance * scale)
      break;
    if (it == kMaxIterations || !r.allFinite())
      throw NumericalError(fmt::format(
          "{}: local Newton for the {} return did not converge (yield residual {:g} after {} "
          "iterations)",
          model.name(), to_string(type), r.cwiseAbs().maxCoeff(), it));
    dg -= J.inverse() * r;
  }

  PrincipalReturn out;
  out.type = type;
  out.stress = sigma;
  out.kappa = kappa;
  out.elastic_strain = eps - b * dg;
  out.tangent = (Mat3::Identity() + Db * J.inverse() * A) * D;
  return out;
}

} // namespace

MohrCoulomb::MohrCoulomb(const LameParameters& lame, const FrictionalStrengthParameters& strength)
    : PlasticModel(lame), strength_(strength) {}

double MohrCoulomb::yield_function(const Vec3& stress, double kappa) const {
  const double hi = stress.maxCoeff(), lo = stress.minCoeff();
  const StrengthState s = strength_.at(kappa);
  const double sp = std::sin(s.friction);
  return (1.0 + sp) * hi - (1.0 - sp) * lo - 2.0 * s.cohesion * std::cos(s.friction);
}

PrincipalReturn MohrCoulomb::return_sorted(const Vec3& eps, double kappa) const {
  const Vec3 trial = elastic_stress(eps);
  if (yield_function(trial, kappa) <= 0.0)
    return {trial, elastic_stiffness(), eps, kappa, ReturnType::Elastic};

  const PrincipalReturn plane =
      return_to_planes<1>(*this, strength_, {Plane{0, 2}}, eps, kappa, ReturnType::Surface);
  if (plane.stress(0) >= plane.stress(1) && plane.stress(1) >= plane.stress(2))
    return plane;

  const double sin_psi = std::sin(strength_.dilation());
  if ((1.0 - sin_psi) * trial(0) - 2.0 * trial(1) + (1.0 + sin_psi) * trial(2) >= 0.0) {
    const PrincipalReturn edge = return_to_planes<2>(*this, strength_, {Plane{0, 2}, Plane{0, 1}},
                                                     eps, kappa, ReturnType::ExtensionEdge);
    if (edge.stress(0) >= edge.stress(1))
      return edge;
  } else {
    const PrincipalReturn edge = return_to_planes<2>(*this, strength_, {Plane{0, 2}, Plane{1, 2}},
                                                     eps, kappa, ReturnType::CompressionEdge);
    if (edge.stress(1) >= edge.stress(2))
      return edge;
  }
  return apex_return(eps, kappa);
}

PrincipalReturn MohrCoulomb::apex_return(const Vec3& eps, double kappa) const {
  if (!strength_.frictional()) // edges of a prism (phi = 0) never end: unreachable
    throw NumericalError(fmt::format("{}: the edge return failed and phi = 0 has no apex", name()));
  const Vec3 e = deviator(eps);
  const double rho = e.norm();
  PrincipalReturn out;
  out.type = ReturnType::Apex;
  out.kappa = kappa + std::sqrt(2.0 / 3.0) * rho;
  const StrengthState s = strength_.at(out.kappa);
  const double sp = std::sin(s.friction), cot = std::cos(s.friction) / sp;
  // p = c cot(phi), dp/dkappa = c' cot(phi) - c phi' / sin^2(phi)
  const double p = s.cohesion * cot;
  const double dp = s.cohesion_slope * cot - s.cohesion * s.friction_slope / (sp * sp);
  out.stress = Vec3::Constant(p);
  out.elastic_strain = Vec3::Constant(p / (3.0 * lame().lambda + 2.0 * lame().mu));
  if (rho > 0.0)
    out.tangent = (std::sqrt(2.0 / 3.0) * dp / rho) * Vec3::Ones() * e.transpose();
  return out;
}

} // namespace talus
