#pragma once
// The water's block of a material point's implicit tangent. The point's force on node i holds
// N_i det(dF) V_n grad u (implicit_trial_state.hpp: the water's pressure on the body's faces,
// written over its volume, with u and its gradient held through the step); only the current
// volume moves with the increment, d det(dF)/d dF_cb = det(dF) dF^-1_bc, so
//     K_(i a),(j c) = N_i (V_n grad u)_a det(dF) (sum_b dF^-1_bc dN_j/dx_b
//                                                  + [c = r] dF^-1_33 N_j / r_n),
// the hoop term in axisymmetry only. The block is not symmetric: a case with water is solved
// by LU.
#include "talus/core/types.hpp"

#include <Eigen/Core>

namespace talus {

/// d det(dF) / d du_(j c) for a stencil of kNodes nodes (column Dim j + c): grads their weight
/// gradients, hoop their N / r_n (axisymmetry; unused otherwise), dF the 3x3 step gradient.
template <int Dim, bool Axisymmetric, int kNodes>
Eigen::Matrix<double, 1, Dim * kNodes>
volume_change_gradient(const Eigen::Matrix<double, Dim, kNodes>& grads,
                       const Eigen::Matrix<double, 1, kNodes>& hoop, const Mat3& dF) {
  const double det = dF.determinant();
  const Mat3 inv = dF.inverse();
  Eigen::Matrix<double, 1, Dim * kNodes> d_det;
  for (int j = 0; j < kNodes; ++j)
    for (int c = 0; c < Dim; ++c) {
      double v = inv.col(c).template head<Dim>().dot(grads.col(j));
      if constexpr (Axisymmetric)
        if (c == 0)
          v += inv(2, 2) * hoop[j];
      d_det[Dim * j + c] = det * v;
    }
  return d_det;
}

/// K += the water's block for a stencil of kNodes nodes: weights their N, grads their weight
/// gradients, hoop their N / r_n (axisymmetry; unused otherwise); dF the 3x3 step gradient and
/// water_force the point's V_n grad u.
template <int Dim, bool Axisymmetric, int kNodes, class Matrix>
void add_water_stiffness(const Eigen::Matrix<double, 1, kNodes>& weights,
                         const Eigen::Matrix<double, Dim, kNodes>& grads,
                         const Eigen::Matrix<double, 1, kNodes>& hoop, const Mat3& dF,
                         const Vec<Dim>& water_force, Matrix& K) {
  const Eigen::Matrix<double, 1, Dim* kNodes> d_det =
      volume_change_gradient<Dim, Axisymmetric, kNodes>(grads, hoop, dF);
  for (int i = 0; i < kNodes; ++i)
    for (int a = 0; a < Dim; ++a)
      if (water_force[a] != 0.0)
        K.row(Dim * i + a) += (weights[i] * water_force[a]) * d_det;
}

} // namespace talus
