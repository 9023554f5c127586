#include "talus/material/plasticity/elastoplastic_response.hpp"

#include "talus/core/errors.hpp"
#include "talus/material/principal_space.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>

namespace talus {

PlasticHistory PlasticHistory::initial(Kinematics kind) {
  PlasticHistory h;
  if (kind == Kinematics::FiniteStrain)
    h.elastic = Mat3::Identity();
  return h;
}

namespace {

/// The trial state in the principal frame.
struct Trial {
  SpectralDecomposition frame; ///< of b_e^tr (finite) or eps^tr (small)
  Vec3 strain;                 ///< principal trial elastic strain
  Mat3 FA;                     ///< finite strain: F A, with b_e^tr = (F A) F^T
};

void check_jacobian(const PlasticModel& model, const Mat3& F, const char* which) {
  const double J = F.determinant();
  if (!(J > 0.0))
    throw NumericalError(fmt::format("{}: det {} = {:g} is not positive", model.name(), which, J));
}

Trial make_trial(const PlasticModel& model, Kinematics kind, const Mat3& F_new, const Mat3& F_old,
                 const PlasticHistory& converged) {
  check_jacobian(model, F_new, "F");
  Trial t;
  if (kind == Kinematics::SmallStrain) {
    // eps^tr = eps_e,n + sym(F) - sym(F_n): the -I of eps(F) cancels
    const Mat3 dF = F_new - F_old;
    t.frame = spectral_decomposition(converged.elastic + 0.5 * (dF + dF.transpose()));
    t.strain = t.frame.values;
    return t;
  }
  check_jacobian(model, F_old, "F_n");
  const Mat3 F_old_inv = F_old.inverse();
  const Mat3 A = F_old_inv * converged.elastic * F_old_inv.transpose();
  t.FA = F_new * A;
  t.frame = spectral_decomposition(t.FA * F_new.transpose());
  if (!(t.frame.values.minCoeff() > 0.0))
    throw NumericalError(fmt::format("{}: trial elastic left Cauchy-Green tensor is not positive "
                                     "definite (smallest eigenvalue {:g})",
                                     model.name(), t.frame.values.minCoeff()));
  t.strain = 0.5 * t.frame.values.array().log().matrix();
  return t;
}

/// tau (Kirchhoff) and the updated history from the principal return.
Mat3 finish(Kinematics kind, const Mat3& F_new, const Trial& t, const PrincipalReturn& r,
            PlasticHistory& updated) {
  updated.kappa = r.kappa;
  const Mat3 stress = from_principal(t.frame, r.stress);
  if (kind == Kinematics::SmallStrain) {
    updated.elastic = from_principal(t.frame, r.elastic_strain);
    return stress * F_new.transpose();
  }
  updated.elastic = from_principal(t.frame, (2.0 * r.elastic_strain).array().exp().matrix());
  return stress;
}

/// (sigma_a - sigma_b) / (eps_a - eps_b) of the principal return, with sigma_a - sigma_b =
/// 2 mu (eps^e_a - eps^e_b); the coincident limit below the relative gap tolerance.
Mat3 strain_divided_differences(const Vec3& eps, const PrincipalReturn& r, double mu) {
  const double scale = eps.cwiseAbs().maxCoeff();
  const Mat3& C = r.tangent;
  Mat3 theta = Mat3::Zero();
  for (int a = 0; a < 3; ++a)
    for (int b = a + 1; b < 3; ++b) {
      const double gap = eps(a) - eps(b);
      theta(a, b) = theta(b, a) =
          std::abs(gap) <= kCoincidentEigenvalueTolerance * scale
              ? 0.5 * ((C(a, a) - C(a, b)) + (C(b, b) - C(b, a)))
              : 2.0 * mu * (r.elastic_strain(a) - r.elastic_strain(b)) / gap;
    }
  return theta;
}

} // namespace

Mat3 elastoplastic_kirchhoff(const PlasticModel& model, Kinematics kind, const Mat3& F_new,
                             const Mat3& F_old, const PlasticHistory& converged,
                             PlasticHistory& updated, ReturnType* type) {
  const Trial t = make_trial(model, kind, F_new, F_old, converged);
  const PrincipalReturn r = model.return_map(t.strain, converged.kappa);
  if (type)
    *type = r.type;
  return finish(kind, F_new, t, r, updated);
}

StressTangent elastoplastic_response(const PlasticModel& model, Kinematics kind, const Mat3& F_new,
                                     const Mat3& F_old, const PlasticHistory& converged,
                                     PlasticHistory& updated, ReturnType* type) {
  const Trial t = make_trial(model, kind, F_new, F_old, converged);
  const PrincipalReturn r = model.return_map(t.strain, converged.kappa);
  if (type)
    *type = r.type;
  StressTangent out;
  out.kirchhoff = finish(kind, F_new, t, r, updated);
  Mat3 theta = strain_divided_differences(t.strain, r, model.lame().mu);

  if (kind == Kinematics::FiniteStrain) {
    // chain with eps = ln(x) / 2: D_ab = C_ab / (2 x_b), theta times (eps_a - eps_b)/(x_a - x_b)
    const Vec3& x = t.frame.values;
    Mat3 D;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        D(a, b) = r.tangent(a, b) / (2.0 * x(b));
    for (int a = 0; a < 3; ++a)
      for (int b = a + 1; b < 3; ++b) {
        const double lo = std::min(x(a), x(b)), hi = std::max(x(a), x(b));
        const double d = (hi - lo) / lo;
        const double ratio = d > 0.0 ? std::log1p(d) / d : 1.0;
        theta(a, b) = theta(b, a) = theta(a, b) * ratio / (2.0 * lo);
      }
    out.dtau_dF = isotropic_function_of_b_derivative(t.frame.vectors, D, theta, t.FA);
    return out;
  }

  // small strain: tau = sigma F^T with dsigma/dF = dsigma/deps (minor-symmetric, acts on sym dF)
  const Mat9 L = isotropic_function_derivative(t.frame.vectors, r.tangent, theta);
  const Mat3 sigma = from_principal(t.frame, r.stress);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k)
        for (int l = 0; l < 3; ++l) {
          double v = 0;
          for (int m = 0; m < 3; ++m)
            v += L(flat_index(i, m), flat_index(k, l)) * F_new(j, m);
          if (j == k)
            v += sigma(i, l);
          out.dtau_dF(flat_index(i, j), flat_index(k, l)) = v;
        }
  return out;
}

} // namespace talus
