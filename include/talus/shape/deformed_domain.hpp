#pragma once
// The particle domain a shape function averages over. uGIMP keeps the initial half-widths;
// cpGIMP stretches them with the point (as AMPLE does, Coombs & Augarde 2020):
//     lp_d = lp0_d U_dd,   F = R U (polar decomposition, U = sqrt(F^T F)).
// Why U and not F: F_dd (Wallstedt & Guilkey 2008) mixes in rotation, so a point turned by
// 90 degrees would get a domain of zero width; the deformed edge length |F e_d| = sqrt(C_dd) is
// free of rotation but grows under isochoric simple shear by sqrt(1 + gamma^2), while U_dd is
// exact for stretches along the grid axes (the compressed column) and grows less under shear.
// U is that of the grid's axes (the in-plane block in 2D: the hoop stretch of axisymmetry
// does not widen a domain in the r-z plane).
#include "talus/core/particles.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>

namespace talus {

/// diag(U) of the right stretch tensor of F (Dim x Dim).
template <int Dim> Vec<Dim> right_stretch_diagonal(const Mat<Dim>& F) {
  const Mat<Dim> C = F.transpose() * F;
  if constexpr (Dim == 2) {
    // U = (C + sqrt(det C) I) / sqrt(tr C + 2 sqrt(det C)) (Cayley-Hamilton for 2 x 2).
    const double s = std::sqrt(C.determinant());
    const double t = std::sqrt(C.trace() + 2.0 * s);
    return Vec<2>((C(0, 0) + s) / t, (C(1, 1) + s) / t);
  } else {
    const Eigen::SelfAdjointEigenSolver<Mat<Dim>> eig(C);
    const Mat<Dim>& Q = eig.eigenvectors();
    const Vec<Dim> stretch = eig.eigenvalues().cwiseMax(0.0).cwiseSqrt();
    return Q.cwiseAbs2() * stretch; // U_dd = sum_k Q_dk^2 lambda_k
  }
}

/// Point s's domain half-widths along the grid axes as Shape sees them.
template <int Dim, class Shape>
Vec<Dim> domain_half_widths(const Particles<Dim>& particles, std::size_t s) {
  if constexpr (Shape::kDomainFollowsStretch)
    return particles.half_size0[s].cwiseProduct(right_stretch_diagonal<Dim>(particles.grid_F(s)));
  else
    return particles.half_size0[s];
}

} // namespace talus
