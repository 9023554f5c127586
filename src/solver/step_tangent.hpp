#pragma once
// The step tangent of the implicit solver: the derivative of the first Piola stress of a step,
//   G = tau(dF F_n) dF^-T   (times V0 it is the point's internal-force density),
// with respect to the step's deformation gradient dF, restricted to the Dim x Dim block that
// grad(du) reaches (plane strain: dF33 = 1). Index Dim a + b for G_ab and dF_ab. The material
// supplies dtau/dF in full 3x3 (stress_tangent.hpp); the chain rule through F = dF F_n and
// the derivative of dF^-T give
//   dG_ab/ddF_cd = sum_q D_aq,cd dFinv_bq - sum_q tau_aq dFinv_bc dFinv_dq,
//   D_aq,cd = dtau_aq/ddF_cd = sum_m dtau_aq/dF_cm Fn_dm.
// With F-bar (f_bar.hpp) the stress is taken at dF_bar = k dF, k = (J_bar / j)^(1/Dim), and
// the force keeps the true volume, G = r tau(dF_bar F_n) dF^-T with r = j / J_bar; at fixed
// J_bar, since dj/ddF = j dF^-T and dk/ddF = -(k / Dim) dF^-T,
//   dG_ab/ddF_cd = r [dFinv_dc G'_ab + sum_q (k D_aq,cd - (k / Dim) dFinv_dc E_aq) dFinv_bq
//                     - sum_q tau_aq dFinv_bc dFinv_dq],       G' = tau dF^-T,
// where E_aq = sum_cd D_aq,cd dF_cd; and at fixed dF
//   dG_ab/dJ_bar = -G_ab / J_bar + r k / (Dim J_bar) sum_q E_aq dFinv_bq.
#include "talus/core/types.hpp"
#include "talus/material/stress_tangent.hpp"

#include <cmath>

namespace talus {

template <int Dim> using StepTangent = Eigen::Matrix<double, Dim * Dim, Dim * Dim>;

/// F-bar's scale k = (J_bar / j)^(1/Dim) of the step gradient, from the ratio J_bar / j.
template <int Dim> double f_bar_scale(double volume_ratio) {
  return Dim == 2 ? std::sqrt(volume_ratio) : std::cbrt(volume_ratio);
}

namespace step_tangent_detail {

/// D (row 3 a + q, column Dim c + d) = dtau_aq/ddF_cd for a, c, d < Dim and q < 3.
template <int Dim>
Eigen::Matrix<double, 3 * Dim, Dim * Dim> stress_rate(const Mat3& Fn, const StressTangent& st) {
  Eigen::Matrix<double, 3 * Dim, Dim * Dim> D;
  for (int a = 0; a < Dim; ++a)
    for (int q = 0; q < 3; ++q)
      for (int c = 0; c < Dim; ++c)
        for (int d = 0; d < Dim; ++d) {
          double v = 0;
          for (int m = 0; m < 3; ++m)
            v += st.dtau_dF(3 * a + q, 3 * c + m) * Fn(d, m);
          D(3 * a + q, Dim * c + d) = v;
        }
  return D;
}

} // namespace step_tangent_detail

/// dG/d(dF) without F-bar; `st` is the material's response at dF F_n.
template <int Dim>
StepTangent<Dim> step_tangent(const Mat<Dim>& dF, const Mat3& Fn, const StressTangent& st) {
  const Mat3 dFinv = embedded<Dim>(dF).inverse();
  const auto D = step_tangent_detail::stress_rate<Dim>(Fn, st);
  StepTangent<Dim> A;
  for (int a = 0; a < Dim; ++a)
    for (int b = 0; b < Dim; ++b)
      for (int c = 0; c < Dim; ++c)
        for (int d = 0; d < Dim; ++d) {
          double v = 0;
          for (int q = 0; q < 3; ++q)
            v += D(3 * a + q, Dim * c + d) * dFinv(b, q) -
                 st.kirchhoff(a, q) * dFinv(b, c) * dFinv(d, q);
          A(Dim * a + b, Dim * c + d) = v;
        }
  return A;
}

/// The F-bar dG/d(dF) at fixed J_bar; `st` is the response at dF_bar F_n, j = det dF, and
/// dG_dJbar receives dG/dJ_bar at fixed dF.
template <int Dim>
StepTangent<Dim> f_bar_step_tangent(const Mat<Dim>& dF, const Mat3& Fn, const StressTangent& st,
                                    double j, double j_bar, Mat<Dim>& dG_dJbar) {
  const Mat3 dFinv = embedded<Dim>(dF).inverse();
  const double r = j / j_bar, k = f_bar_scale<Dim>(j_bar / j);
  const auto D = step_tangent_detail::stress_rate<Dim>(Fn, st);
  const Eigen::Matrix<double, 3 * Dim, 1> E =
      D * Eigen::Map<const Eigen::Matrix<double, Dim * Dim, 1>>(Mat<Dim>(dF.transpose()).data());
  const Mat3 G_prime = st.kirchhoff * dFinv.transpose();
  StepTangent<Dim> A;
  for (int a = 0; a < Dim; ++a)
    for (int b = 0; b < Dim; ++b) {
      double e_term = 0;
      for (int q = 0; q < 3; ++q)
        e_term += E(3 * a + q) * dFinv(b, q);
      dG_dJbar(a, b) = -r * G_prime(a, b) / j_bar + r * k / (Dim * j_bar) * e_term;
      for (int c = 0; c < Dim; ++c)
        for (int d = 0; d < Dim; ++d) {
          double v = dFinv(d, c) * G_prime(a, b);
          for (int q = 0; q < 3; ++q)
            v += k * (D(3 * a + q, Dim * c + d) - dFinv(d, c) * E(3 * a + q) / Dim) * dFinv(b, q) -
                 st.kirchhoff(a, q) * dFinv(b, c) * dFinv(d, q);
          A(Dim * a + b, Dim * c + d) = r * v;
        }
    }
  return A;
}

} // namespace talus
