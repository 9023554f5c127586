#include "talus/material/hyperelastic.hpp"

#include "talus/core/errors.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>

namespace talus {

namespace {

double positive_jacobian(const Mat3& F, const char* model) {
  const double J = F.determinant();
  if (!(J > 0.0))
    throw NumericalError(fmt::format("{}: det F = {:g} is not positive", model, J));
  return J;
}

/// Principal Kirchhoff stresses of the Hencky law from the eigenvalues x of b.
Vec3 hencky_principal_stress(const Vec3& x, const LameParameters& lame) {
  const Vec3 e = 0.5 * x.array().log().matrix();
  return Vec3::Constant(lame.lambda * e.sum()) + 2.0 * lame.mu * e;
}

} // namespace

namespace {
// Small-strain energy W = lambda/2 (tr eps)^2 + mu eps:eps with eps = sym(F) - I; its first
// Piola stress P = dW/dF = lambda tr(eps) I + 2 mu eps.
Mat3 small_strain_piola(const Mat3& F, const LameParameters& lame) {
  const Mat3 eps = 0.5 * (F + F.transpose()) - Mat3::Identity();
  return lame.lambda * eps.trace() * Mat3::Identity() + 2.0 * lame.mu * eps;
}
} // namespace

Mat3 linear_elastic_kirchhoff(const Mat3& F, const LameParameters& lame) {
  return small_strain_piola(F, lame) * F.transpose();
}

StressTangent linear_elastic_response(const Mat3& F, const LameParameters& lame) {
  // tau = P F^T, so dtau_ij/dF_kl = sum_m dP_im/dF_kl F_jm + P_il delta_jk with
  // dP_im/dF_kl = lambda delta_im delta_kl + mu (delta_ik delta_ml + delta_il delta_mk).
  const Mat3 P = small_strain_piola(F, lame);
  StressTangent r;
  r.kirchhoff = P * F.transpose();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k)
        for (int l = 0; l < 3; ++l) {
          double v = 0;
          for (int m = 0; m < 3; ++m) {
            const double dP = lame.lambda * (i == m) * (k == l) +
                              lame.mu * ((i == k) * (m == l) + (i == l) * (m == k));
            v += dP * F(j, m);
          }
          if (j == k)
            v += P(i, l);
          r.dtau_dF(flat_index(i, j), flat_index(k, l)) = v;
        }
  return r;
}

Mat3 neo_hookean_kirchhoff(const Mat3& F, const LameParameters& lame) {
  const double J = positive_jacobian(F, "neo-Hookean");
  return lame.mu * (F * F.transpose() - Mat3::Identity()) +
         lame.lambda * std::log(J) * Mat3::Identity();
}

StressTangent neo_hookean_response(const Mat3& F, const LameParameters& lame) {
  StressTangent r;
  r.kirchhoff = neo_hookean_kirchhoff(F, lame);
  // d ln J / d F = F^{-T}
  const Vec9 dlnJ = flatten(F.inverse().transpose());
  r.dtau_dF = lame.mu * left_cauchy_green_derivative(F);
  for (int i = 0; i < 3; ++i)
    r.dtau_dF.row(flat_index(i, i)) += lame.lambda * dlnJ.transpose();
  return r;
}

Mat3 hencky_kirchhoff(const Mat3& F, const LameParameters& lame) {
  positive_jacobian(F, "Hencky");
  const SpectralDecomposition s = spectral_decomposition(F * F.transpose());
  return from_principal(s, hencky_principal_stress(s.values, lame));
}

StressTangent hencky_response(const Mat3& F, const LameParameters& lame) {
  positive_jacobian(F, "Hencky");
  const SpectralDecomposition s = spectral_decomposition(F * F.transpose());
  const Vec3& x = s.values;
  StressTangent r;
  r.kirchhoff = from_principal(s, hencky_principal_stress(x, lame));

  // tau_a = lambda sum_b e_b + 2 mu e_a, e_a = ln(x_a) / 2  =>  D_ab = (lambda + 2 mu d_ab)/(2 x_b)
  Mat3 D;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b)
      D(a, b) = (lame.lambda + (a == b ? 2.0 * lame.mu : 0.0)) / (2.0 * x(b));
  // theta_ab = (tau_a - tau_b) / (x_a - x_b) = mu (ln x_a - ln x_b) / (x_a - x_b). With x_b the
  // smaller eigenvalue and d = (x_a - x_b) / x_b >= 0 this is mu / x_b * log1p(d) / d, free of
  // cancellation for any gap, and mu / x_b (the limit) when d = 0.
  Mat3 theta = Mat3::Zero();
  for (int a = 0; a < 3; ++a)
    for (int b = a + 1; b < 3; ++b) {
      const double lo = std::min(x(a), x(b)), hi = std::max(x(a), x(b));
      const double d = (hi - lo) / lo;
      const double ratio = d > 0.0 ? std::log1p(d) / d : 1.0;
      theta(a, b) = theta(b, a) = lame.mu / lo * ratio;
    }
  r.dtau_dF = isotropic_function_of_b_derivative(s.vectors, D, theta, F);
  return r;
}

} // namespace talus
