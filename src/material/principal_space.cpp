#include "talus/material/principal_space.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

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

namespace {

/// A whose third axis is uncoupled (A(2, 0) = A(2, 1) = 0, as plane strain and axisymmetry keep
/// b and tau): the in-plane 2 x 2 block by its rotation angle, from atan2, so any gap is
/// resolved, with Rayleigh quotients for the values; then all three ascending.
SpectralDecomposition block_spectral_decomposition(const Mat3& A) {
  const double half_gap = 0.5 * (A(0, 0) - A(1, 1)), b = A(1, 0);
  const double angle = 0.5 * std::atan2(b, half_gap); // the larger eigenvalue's direction
  const double c = std::cos(angle), s = std::sin(angle);
  const double rayleigh_larger = c * c * A(0, 0) + 2.0 * c * s * b + s * s * A(1, 1);
  const double rayleigh_smaller = s * s * A(0, 0) - 2.0 * c * s * b + c * c * A(1, 1);
  // Equal in exact arithmetic when the block is a multiple of I; keep the order under rounding.
  const double larger = std::max(rayleigh_larger, rayleigh_smaller);
  const double smaller = std::min(rayleigh_larger, rayleigh_smaller);
  const std::array<std::pair<double, Vec3>, 3> pairs = {std::pair{smaller, Vec3(-s, c, 0.0)},
                                                        std::pair{larger, Vec3(c, s, 0.0)},
                                                        std::pair{A(2, 2), Vec3(0.0, 0.0, 1.0)}};
  std::array<int, 3> order = {0, 1, 2}; // smaller <= larger: place the out-of-plane value
  if (A(2, 2) < larger)
    order = A(2, 2) < smaller ? std::array<int, 3>{2, 0, 1} : std::array<int, 3>{0, 2, 1};
  SpectralDecomposition d;
  for (int a = 0; a < 3; ++a) {
    d.values(a) = pairs[static_cast<std::size_t>(order[static_cast<std::size_t>(a)])].first;
    d.vectors.col(a) = pairs[static_cast<std::size_t>(order[static_cast<std::size_t>(a)])].second;
  }
  return d;
}

} // namespace

SpectralDecomposition spectral_decomposition(const Mat3& A) {
  if (A(2, 0) == 0.0 && A(2, 1) == 0.0)
    return block_spectral_decomposition(A);
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

namespace {

/// The principal dyads of an isotropic function's derivative, one flattened tensor per row:
/// E_a = n_a n_a^T, and S_c = (n_a n_b^T + n_b n_a^T) / 2 for the pairs c = (a, b) = (0, 1),
/// (0, 2), (1, 2) with their weights 2 theta_ab. Every one is symmetric.
struct PrincipalDyads {
  Mat3 E[3], S[3];
  Vec3 weight;
  PrincipalDyads(const Mat3& eigenvectors, const Mat3& theta) {
    constexpr int kPairs[3][2] = {{0, 1}, {0, 2}, {1, 2}};
    for (int a = 0; a < 3; ++a)
      E[a] = eigenvectors.col(a) * eigenvectors.col(a).transpose();
    for (int c = 0; c < 3; ++c) {
      const int a = kPairs[c][0], b = kPairs[c][1];
      const Mat3 nanb = eigenvectors.col(a) * eigenvectors.col(b).transpose();
      S[c] = 0.5 * (nanb + nanb.transpose());
      weight[c] = 2.0 * theta(a, b);
    }
  }
  /// The rows flatten(X_a M) of the dyads X (E or S) times M (the identity: the dyads).
  static Eigen::Matrix<double, 3, 9> rows(const Mat3 (&X)[3], const Mat3& M) {
    Eigen::Matrix<double, 3, 9> R;
    for (int a = 0; a < 3; ++a)
      R.row(a) = flatten(X[a] * M).transpose();
    return R;
  }
};

} // namespace

// L = sum_{a,b} D_ab E_a (x) E_b + sum_{a<b} 2 theta_ab S_ab (x) S_ab, as products of the 3 x 9
// matrices of the dyads: L = E^T D E + S^T diag(2 theta) S. Every factor is a symmetric tensor,
// so L has minor symmetry in (i, j) and in (k, l); S_ab : dA = n_a . dA n_b for symmetric dA.
Mat9 isotropic_function_derivative(const Mat3& eigenvectors, const Mat3& df_dx, const Mat3& theta) {
  const PrincipalDyads d(eigenvectors, theta);
  const auto E = PrincipalDyads::rows(d.E, Mat3::Identity());
  const auto S = PrincipalDyads::rows(d.S, Mat3::Identity());
  // lazyProduct: coefficient loops; Eigen's GEMM path costs more than the 243 products here.
  const Eigen::Matrix<double, 3, 9> DE = df_dx * E, WS = d.weight.asDiagonal() * S;
  return E.transpose().lazyProduct(DE) + S.transpose().lazyProduct(WS);
}

// (L dB)(r, kl) = sum_ij L(r, ij) (delta_ik F_jl + delta_jk F_il) = 2 sum_j L(r, kj) F_jl by the
// minor symmetry of L; in L's dyad form each column dyad X(kj) becomes (X F)(k, l). This costs
// a quarter of forming L and multiplying by the 9 x 9 dB.
Mat9 isotropic_function_of_b_derivative(const Mat3& eigenvectors, const Mat3& df_dx,
                                        const Mat3& theta, const Mat3& F) {
  const PrincipalDyads d(eigenvectors, theta);
  const auto E = PrincipalDyads::rows(d.E, Mat3::Identity());
  const auto S = PrincipalDyads::rows(d.S, Mat3::Identity());
  const auto EF = PrincipalDyads::rows(d.E, F);
  const auto SF = PrincipalDyads::rows(d.S, F);
  const Eigen::Matrix<double, 3, 9> DEF = df_dx * EF, WSF = d.weight.asDiagonal() * SF;
  return 2.0 * (E.transpose().lazyProduct(DEF) + S.transpose().lazyProduct(WSF));
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
