#pragma once
// The step tangent of the implicit solver: the derivative of the first Piola stress of a step,
//   G = tau(dF F_n) dF^-T   (times V0 it is the point's internal-force density),
// with respect to the components of the step's deformation gradient dF that the grid's motion
// reaches (StepComponents): the Dim x Dim block of grad(du) (plane strain: dF33 = 1), and in
// axisymmetry the hoop stretch dF33 = 1 + u_r / r. The material supplies dtau/dF in full 3x3
// (stress_tangent.hpp); the chain rule through F = dF F_n and the derivative of dF^-T give,
// for components (a, b) and (c, d) in 3x3 indices,
//   dG_ab/ddF_cd = sum_q D_aq,cd dFinv_bq - sum_q tau_aq dFinv_bc dFinv_dq,
//   D_aq,cd = dtau_aq/ddF_cd = sum_m dtau_aq/dF_cm Fn_dm.
// With F-bar (f_bar.hpp) the stress is taken at dF_bar = k dF, k = (J_bar / j)^(1/n) over the
// n axes the step's volume change spreads over (StepComponents::kAxes, or 3 in plane strain with
// solver.f_bar_out_of_plane, where dF_bar33 = k moves although dF33 = 1 does not), and the force
// keeps the true volume, G = r tau(dF_bar F_n) dF^-T with r = j / J_bar; at fixed J_bar, since
// dj/ddF = j dF^-T and dk/ddF = -(k / n) dF^-T,
//   dG_ab/ddF_cd = r [dFinv_dc G'_ab + sum_q (k D_aq,cd - (k / n) dFinv_dc E_aq) dFinv_bq
//                     - sum_q tau_aq dFinv_bc dFinv_dq],       G' = tau dF^-T,
// where E_aq = sum_cd D_aq,cd dF_cd over every component k scales (with the out-of-plane
// spread, plane strain's fixed dF33 = 1 too); and at fixed dF
//   dG_ab/dJ_bar = -G_ab / J_bar + r k / (n J_bar) sum_q E_aq dFinv_bq.
#include "talus/core/types.hpp"
#include "talus/material/stress_tangent.hpp"

#include <cmath>

namespace talus {

/// The components of the step gradient that the grid's motion reaches, numbered: dF_ab of the
/// Dim x Dim block at Dim a + b, and in axisymmetry the hoop stretch dF33 at Dim^2.
template <int Dim, bool Axisymmetric> struct StepComponents {
  static_assert(Dim == 2 || !Axisymmetric, "axisymmetry is a 2D geometry");
  static constexpr int kCount = Dim * Dim + (Axisymmetric ? 1 : 0);
  static constexpr int kHoop = Dim * Dim; ///< the hoop component's number (axisymmetry)
  /// The axes a step's volume change spreads over: the grid's, and the hoop direction.
  static constexpr int kAxes = Dim + (Axisymmetric ? 1 : 0);
  /// The rows of tau that the components' G reach (0 .. kStressRows - 1).
  static constexpr int kStressRows = Axisymmetric ? 3 : Dim;
  static constexpr int row(int k) { return k < Dim * Dim ? k / Dim : 2; }
  static constexpr int col(int k) { return k < Dim * Dim ? k % Dim : 2; }

  /// The 3x3 step gradient of the block dF and the hoop stretch (1 unless axisymmetric).
  static Mat3 embed(const Mat<Dim>& dF, double hoop) {
    Mat3 full = embedded<Dim>(dF);
    if constexpr (Axisymmetric)
      full(2, 2) = hoop;
    return full;
  }
  /// The components' values, in their numbering.
  static Eigen::Matrix<double, kCount, 1> values(const Mat3& dF) {
    Eigen::Matrix<double, kCount, 1> v;
    for (int k = 0; k < kCount; ++k)
      v[k] = dF(row(k), col(k));
    return v;
  }
};

template <int Dim, bool Axisymmetric>
using StepTangent = Eigen::Matrix<double, StepComponents<Dim, Axisymmetric>::kCount,
                                  StepComponents<Dim, Axisymmetric>::kCount>;
template <int Dim, bool Axisymmetric>
using StepVector = Eigen::Matrix<double, StepComponents<Dim, Axisymmetric>::kCount, 1>;

/// F-bar's scale k = (J_bar / j)^(1/axes) of the step gradient, from the ratio J_bar / j.
inline double f_bar_scale(int axes, double volume_ratio) {
  return axes == 2 ? std::sqrt(volume_ratio) : std::cbrt(volume_ratio);
}

namespace step_tangent_detail {

/// D (row 3 a + q, column k = (c, d)) = dtau_aq/ddF_cd for a < kStressRows, q < 3.
template <int Dim, bool Axisymmetric>
Eigen::Matrix<double, 3 * StepComponents<Dim, Axisymmetric>::kStressRows,
              StepComponents<Dim, Axisymmetric>::kCount>
stress_rate(const Mat3& Fn, const StressTangent& st) {
  using C = StepComponents<Dim, Axisymmetric>;
  Eigen::Matrix<double, 3 * C::kStressRows, C::kCount> D;
  for (int a = 0; a < C::kStressRows; ++a)
    for (int q = 0; q < 3; ++q)
      for (int k = 0; k < C::kCount; ++k) {
        const int c = C::row(k), d = C::col(k);
        double v = 0;
        for (int m = 0; m < 3; ++m)
          v += st.dtau_dF(3 * a + q, 3 * c + m) * Fn(d, m);
        D(3 * a + q, k) = v;
      }
  return D;
}

} // namespace step_tangent_detail

/// dG/d(dF) without F-bar; dF is the 3x3 step gradient, `st` the material's response at dF F_n.
template <int Dim, bool Axisymmetric>
StepTangent<Dim, Axisymmetric> step_tangent(const Mat3& dF, const Mat3& Fn,
                                            const StressTangent& st) {
  using C = StepComponents<Dim, Axisymmetric>;
  const Mat3 dFinv = dF.inverse();
  const auto D = step_tangent_detail::stress_rate<Dim, Axisymmetric>(Fn, st);
  StepTangent<Dim, Axisymmetric> A;
  for (int k1 = 0; k1 < C::kCount; ++k1) {
    const int a = C::row(k1), b = C::col(k1);
    for (int k2 = 0; k2 < C::kCount; ++k2) {
      const int c = C::row(k2), d = C::col(k2);
      double v = 0;
      for (int q = 0; q < 3; ++q)
        v += D(3 * a + q, k2) * dFinv(b, q) - st.kirchhoff(a, q) * dFinv(b, c) * dFinv(d, q);
      A(k1, k2) = v;
    }
  }
  return A;
}

/// The F-bar dG/d(dF) at fixed J_bar; `st` is the response at dF_bar F_n, j = det dF, `axes`
/// the axes the volume change spreads over (C::kAxes, or 3 in plane strain out of plane), and
/// dG_dJbar receives dG/dJ_bar at fixed dF.
template <int Dim, bool Axisymmetric>
StepTangent<Dim, Axisymmetric>
f_bar_step_tangent(const Mat3& dF, const Mat3& Fn, const StressTangent& st, double j, double j_bar,
                   int axes, StepVector<Dim, Axisymmetric>& dG_dJbar) {
  using C = StepComponents<Dim, Axisymmetric>;
  const double n = axes;
  const Mat3 dFinv = dF.inverse();
  const double r = j / j_bar, k = f_bar_scale(axes, j_bar / j);
  const auto D = step_tangent_detail::stress_rate<Dim, Axisymmetric>(Fn, st);
  Eigen::Matrix<double, 3 * C::kStressRows, 1> E = D * C::values(dF);
  if (axes > C::kAxes) // plane strain's dF33 = 1 is scaled too: its column of dtau/d(dF)
    for (int a = 0; a < C::kStressRows; ++a)
      for (int q = 0; q < 3; ++q)
        for (int m = 0; m < 3; ++m)
          E(3 * a + q) += st.dtau_dF(3 * a + q, 6 + m) * Fn(2, m) * dF(2, 2);
  const Mat3 G_prime = st.kirchhoff * dFinv.transpose();
  StepTangent<Dim, Axisymmetric> A;
  for (int k1 = 0; k1 < C::kCount; ++k1) {
    const int a = C::row(k1), b = C::col(k1);
    double e_term = 0;
    for (int q = 0; q < 3; ++q)
      e_term += E(3 * a + q) * dFinv(b, q);
    dG_dJbar(k1) = -r * G_prime(a, b) / j_bar + r * k / (n * j_bar) * e_term;
    for (int k2 = 0; k2 < C::kCount; ++k2) {
      const int c = C::row(k2), d = C::col(k2);
      double v = dFinv(d, c) * G_prime(a, b);
      for (int q = 0; q < 3; ++q)
        v += k * (D(3 * a + q, k2) - dFinv(d, c) * E(3 * a + q) / n) * dFinv(b, q) -
             st.kirchhoff(a, q) * dFinv(b, c) * dFinv(d, q);
      A(k1, k2) = r * v;
    }
  }
  return A;
}

} // namespace talus
