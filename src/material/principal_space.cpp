#include "talus/material/principal_space.hpp"

#include <algorithm>
#include <cmath>

namespace talus {

Vec9 flatten(const Mat3& A) {
  Vec9 v;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      v(flat_index(i, j)) = A(i, j);
  return v;
}

Mat3 unflatten(const Vec9& v) {
  Mat3 A;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      A(i, j) = v(flat_index(i, j));
  return A;
}

SpectralDecomposition spectral_decomposition(const Mat3& A) {
  const Eigen::SelfAdjointEigenSolver<Mat3> solver(A, Eigen::ComputeEigenvectors);
  return {solver.eigenvalues(), solver.eigenvectors()};
}

Mat3 from_principal(const SpectralDecomposition& s, const Vec3& f) {
  return s.vectors * f.asDiagonal() * s.vectors.transpose();
}

Mat3 principal_divided_differences(const Vec3& x, const Vec3& f, const Mat3& df_dx, double tol) {
  const double scale = x.cwiseAbs().maxCoeff();
  Mat3 theta = Mat3::Zero();
  for (int a = 0; a < 3; ++a)
    for (int b = a + 1; b < 3; ++b) {
      const double gap = x(a) - x(b);
      const double t = std::abs(gap) <= tol * scale
                           ? 0.5 * ((df_dx(a, a) - df_dx(a, b)) + (df_dx(b, b) - df_dx(b, a)))
                           : (f(a) - f(b)) / gap;
      theta(a, b) = theta(b, a) = t;
    }
  return theta;
}

Mat9 isotropic_function_derivative(const SpectralDecomposition& s, const Vec3& f,
                                   const Mat3& df_dx) {
  return isotropic_function_derivative(s.vectors, df_dx,
                                       principal_divided_differences(s.values, f, df_dx));
}

Mat9 isotropic_function_derivative(const Mat3& eigenvectors, const Mat3& df_dx, const Mat3& theta) {
  // L = sum_{a,b} D_ab E_a (x) E_b + sum_{a<b} 2 theta_ab S_ab (x) S_ab with E_a = n_a n_a^T and
  // S_ab = (n_a n_b^T + n_b n_a^T) / 2. Every factor is a symmetric tensor, so L has minor
  // symmetry in (i, j) and in (k, l); S_ab : dA = n_a . dA n_b for symmetric dA.
  Vec9 E[3];
  for (int a = 0; a < 3; ++a) {
    const Vec3 n = eigenvectors.col(a);
    E[a] = flatten(n * n.transpose());
  }
  Mat9 L = Mat9::Zero();
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b)
      L.noalias() += df_dx(a, b) * E[a] * E[b].transpose();
  for (int a = 0; a < 3; ++a)
    for (int b = a + 1; b < 3; ++b) {
      const Vec3 na = eigenvectors.col(a), nb = eigenvectors.col(b);
      const Mat3 nanb = na * nb.transpose();
      const Vec9 S = flatten(0.5 * (nanb + nanb.transpose()));
      L.noalias() += (2.0 * theta(a, b)) * S * S.transpose();
    }
  return L;
}

Mat9 left_cauchy_green_derivative(const Mat3& F) {
  Mat9 D = Mat9::Zero();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int l = 0; l < 3; ++l) {
        // d b_ij / d F_il += F_jl (k = i) and d b_ij / d F_jl += F_il (k = j)
        D(flat_index(i, j), flat_index(i, l)) += F(j, l);
        D(flat_index(i, j), flat_index(j, l)) += F(i, l);
      }
  return D;
}

} // namespace talus
