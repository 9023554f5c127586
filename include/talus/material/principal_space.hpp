#pragma once
// Principal-space calculus for isotropic functions of one symmetric 3x3 tensor, shared by the
// hyperelastic models (Hencky) and the principal-space plasticity returns (Mohr-Coulomb,
// Tresca, exponential-map return mapping).
//
// An isotropic tensor function has the spectral form
//     T(A) = sum_a f_a(x) n_a n_a^T,    A = sum_a x_a n_a n_a^T,
// where x = (x_1, x_2, x_3) are the eigenvalues of A, n_a its orthonormal eigenvectors and the
// principal values f_a may depend on all three x_b (a return map in principal stress space
// does). Its derivative (de Souza Neto, Peric & Owen 2008, Appendix A; Miehe 1998; Simo 1992)
// is, for a symmetric increment dA,
//     dT = sum_{a,b} D_ab (n_b . dA n_b) n_a n_a^T
//        + sum_{a<b} theta_ab (n_a . dA n_b) (n_a n_b^T + n_b n_a^T),
// with D_ab = d f_a / d x_b and the divided differences
//     theta_ab = (f_a - f_b) / (x_a - x_b)                       for x_a != x_b,
//     theta_ab = ((D_aa - D_ab) + (D_bb - D_ba)) / 2             for x_a == x_b (the limit).
// The repeated-eigenvalue cases (two or three equal) need no special branch beyond theta:
// the formula above is valid for any orthonormal eigenbasis of a repeated eigenspace.
//
// 9x9 matrices here and in hyperelastic.hpp flatten 3x3 tensors row-major: index 3*i + j holds
// component (i, j), so M(3*i + j, 3*k + l) = d T_ij / d A_kl.
#include "talus/core/types.hpp"

namespace talus {

using Vec9 = Eigen::Matrix<double, 9, 1>;
using Mat9 = Eigen::Matrix<double, 9, 9>;

/// Row-major flat index of tensor component (i, j).
constexpr int flat_index(int i, int j) {
  return 3 * i + j;
}
/// Row-major flattening of a 3x3 tensor.
Vec9 flatten(const Mat3& A);
/// Inverse of flatten.
Mat3 unflatten(const Vec9& v);

/// A = vectors * diag(values) * vectors^T; eigenvalues ascending, eigenvectors as orthonormal
/// columns (vectors.col(a) belongs to values(a)).
struct SpectralDecomposition {
  Vec3 values = Vec3::Zero();
  Mat3 vectors = Mat3::Identity();
};

/// Eigen-decomposition of the symmetric tensor A (only its lower triangle is read). Uses the
/// iterative (QR) solver, accurate also for nearly repeated eigenvalues; a tensor whose third
/// axis is uncoupled (plane strain, axisymmetry) gets the 2 x 2 block's rotation in closed form.
SpectralDecomposition spectral_decomposition(const Mat3& A);

/// sum_a f(a) n_a n_a^T: the tensor with principal values f in the eigenbasis of `s`.
Mat3 from_principal(const SpectralDecomposition& s, const Vec3& f);

/// Relative eigenvalue gap below which two eigenvalues are treated as equal by
/// principal_divided_differences: |x_a - x_b| <= tol * max_c |x_c|. The coincident formula is a
/// trapezoid rule for the divided difference (error O(gap^2)), the quotient loses
/// eps |f| / gap to cancellation; 1e-5 keeps both near 1e-10 for O(1) arguments.
inline constexpr double kCoincidentEigenvalueTolerance = 1e-5;

/// The symmetric matrix of divided differences theta_ab (diagonal zero) from the eigenvalues x,
/// the principal values f and their derivatives df_dx(a, b) = d f_a / d x_b. Pairs closer than
/// `tol` (relative, see above) use the limit formula. Callers that know a cancellation-free
/// closed form for theta (e.g. log, see hyperelastic.cpp) should pass it to
/// isotropic_function_derivative directly instead.
Mat3 principal_divided_differences(const Vec3& x, const Vec3& f, const Mat3& df_dx,
                                   double tol = kCoincidentEigenvalueTolerance);

/// d T / d A (9x9, row-major flattening) of the isotropic tensor function with principal values
/// f and principal derivatives df_dx(a, b) = d f_a / d x_b (need not be diagonal or symmetric)
/// at A = s. The result has minor symmetry in (k, l): it acts on sym(dA), as it must for a
/// function of a symmetric argument.
Mat9 isotropic_function_derivative(const SpectralDecomposition& s, const Vec3& f,
                                   const Mat3& df_dx);

/// Same, with the divided differences theta (symmetric, diagonal ignored) supplied by the caller.
Mat9 isotropic_function_derivative(const Mat3& eigenvectors, const Mat3& df_dx, const Mat3& theta);

/// d T / d F of the isotropic function T(b) of the left Cauchy-Green tensor b = F F^T, with the
/// eigenvectors of b, df_dx and theta as above: isotropic_function_derivative(...) times
/// left_cauchy_green_derivative(F), without forming either.
Mat9 isotropic_function_of_b_derivative(const Mat3& eigenvectors, const Mat3& df_dx,
                                        const Mat3& theta, const Mat3& F);

/// d b / d F for the left Cauchy-Green tensor b = F F^T:
/// (3*i + j, 3*k + l) -> delta_ik F_jl + F_il delta_jk.
Mat9 left_cauchy_green_derivative(const Mat3& F);

} // namespace talus
