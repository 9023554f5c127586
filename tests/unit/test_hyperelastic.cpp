// Kirchhoff stress and consistent tangent dtau/dF of the elastic models (linear elastic,
// neo-Hookean, Hencky) and the principal-space calculus behind Hencky: tangents against central
// finite differences (distinct, double and triple principal stretches, large stretch),
// objectivity, the small-strain limit, Hencky's energy and pure dilatation.
#include "talus/core/errors.hpp"
#include "talus/material/hyperelastic.hpp"
#include "talus/material/material.hpp"
#include "talus/material/principal_space.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

using namespace talus;

namespace {

const LameParameters kLame = LameParameters::from_young_poisson(2.0e7, 0.3);

Mat3 rotation(double angle, const Vec3& axis) {
  return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

Mat3 diag(double a, double b, double c) {
  return Vec3(a, b, c).asDiagonal();
}

Mat2 rotation2(double angle) {
  Mat2 R;
  R << std::cos(angle), -std::sin(angle), std::sin(angle), std::cos(angle);
  return R;
}

const Mat3 kQ1 = rotation(0.7, Vec3(1.0, 2.0, -0.5));
const Mat3 kQ2 = rotation(-1.1, Vec3(-0.3, 0.4, 1.0));

struct NamedF {
  std::string name;
  Mat3 F;
};

/// The deformation gradients every tangent is checked on.
std::vector<NamedF> tangent_cases() {
  Mat2 uniaxial = Mat2::Identity();
  uniaxial(0, 0) = 1.25;
  return {
      {"general (distinct stretches, rotation)", kQ1 * diag(1.3, 0.8, 1.1) * kQ2},
      {"general with shear", Mat3{{1.2, 0.3, -0.1}, {0.05, 0.9, 0.2}, {-0.15, 0.1, 1.05}}},
      {"plane strain, distinct", embedded<2>(rotation2(0.4) * Mat2{{1.3, 0.2}, {0.0, 0.8}})},
      {"plane strain uniaxial (b double: lambda^2, 1, 1)", embedded<2>(rotation2(0.4) * uniaxial)},
      {"plane strain isotropic in-plane (b double: s^2, s^2, 1)",
       embedded<2>(rotation2(0.7) * (1.2 * Mat2::Identity()))},
      {"3D double eigenvalue, general orientation", kQ1 * diag(1.2, 1.2, 0.9) * kQ2},
      {"nearly double eigenvalue (gap 1e-9)", kQ1 * diag(1.2, 1.2 * (1.0 + 1e-9), 0.9) * kQ2},
      {"identity (triple)", Mat3::Identity()},
      {"pure dilatation (triple)", kQ1 * (1.15 * Mat3::Identity())},
      {"large stretch, plane strain (3, 0.3)",
       embedded<2>(rotation2(0.3) * Mat2{{3.0, 0.0}, {0.0, 0.3}})},
      {"large stretch, 3D (3, 0.3, 1.5)", kQ1 * diag(3.0, 0.3, 1.5) * kQ2},
  };
}

using Response = std::function<StressTangent(const Mat3&)>;

/// Central differences of tau with respect to every F_kl, against dtau_dF: relative Frobenius
/// error. Step 1e-6 relative to the largest entry of F: truncation ~ h^2 tau''' and round-off
/// ~ eps |tau| / h are both around 1e-10 relative here.
double tangent_fd_error(const Response& response, const Mat3& F) {
  const StressTangent r = response(F);
  const double h = 1e-6 * std::max(1.0, F.cwiseAbs().maxCoeff());
  Mat9 fd;
  for (int k = 0; k < 3; ++k)
    for (int l = 0; l < 3; ++l) {
      Mat3 Fp = F, Fm = F;
      Fp(k, l) += h;
      Fm(k, l) -= h;
      fd.col(flat_index(k, l)) =
          flatten(response(Fp).kirchhoff - response(Fm).kirchhoff) / (2.0 * h);
    }
  return (fd - r.dtau_dF).norm() / r.dtau_dF.norm();
}

void check_tangent(const char* model, const Response& response) {
  double worst = 0;
  for (const auto& c : tangent_cases()) {
    SCOPED_TRACE(c.name);
    const double err = tangent_fd_error(response, c.F);
    std::printf("[ fd ] %-12s %-58s rel. error %.2e\n", model, c.name.c_str(), err);
    EXPECT_LT(err, 1e-6);
    worst = std::max(worst, err);
  }
  std::printf("[ fd ] %-12s worst %.2e\n", model, worst);
}

double rel(const Mat3& a, const Mat3& b) {
  return (a - b).norm() / b.norm();
}

Mat3 small_strain_stress(const Mat3& F, const LameParameters& lame) {
  const Mat3 eps = 0.5 * (F + F.transpose()) - Mat3::Identity();
  return lame.lambda * eps.trace() * Mat3::Identity() + 2.0 * lame.mu * eps;
}

} // namespace

TEST(HyperelasticTangent, LinearElasticMatchesFiniteDifferences) {
  check_tangent("linear", [](const Mat3& F) { return linear_elastic_response(F, kLame); });
}

TEST(HyperelasticTangent, NeoHookeanMatchesFiniteDifferences) {
  check_tangent("neo-Hookean", [](const Mat3& F) { return neo_hookean_response(F, kLame); });
}

TEST(HyperelasticTangent, HenckyMatchesFiniteDifferences) {
  check_tangent("Hencky", [](const Mat3& F) { return hencky_response(F, kLame); });
}

TEST(HyperelasticTangent, HenckyNearlyIncompressibleMatchesFiniteDifferences) {
  const auto lame = LameParameters::from_young_poisson(2.0e7, 0.499);
  check_tangent("Hencky nu=.499", [&](const Mat3& F) { return hencky_response(F, lame); });
}

TEST(HyperelasticTangent, ResponseStressEqualsStressOnlyFunction) {
  for (const auto& c : tangent_cases()) {
    SCOPED_TRACE(c.name);
    EXPECT_EQ(linear_elastic_response(c.F, kLame).kirchhoff, linear_elastic_kirchhoff(c.F, kLame));
    EXPECT_EQ(neo_hookean_response(c.F, kLame).kirchhoff, neo_hookean_kirchhoff(c.F, kLame));
    EXPECT_EQ(hencky_response(c.F, kLame).kirchhoff, hencky_kirchhoff(c.F, kLame));
  }
}

TEST(HyperelasticObjectivity, NeoHookeanAndHenckyRotateWithF) {
  const Mat3 Q = rotation(2.3, Vec3(0.2, -1.0, 0.6));
  for (const auto& c : tangent_cases()) {
    SCOPED_TRACE(c.name);
    for (auto* fn : {&neo_hookean_kirchhoff, &hencky_kirchhoff}) {
      const Mat3 tau = fn(c.F, kLame);
      const Mat3 rotated = fn(Q * c.F, kLame);
      if (tau.norm() == 0.0)
        EXPECT_LT(rotated.norm(), 1e-9 * kLame.mu);
      else
        EXPECT_LT(rel(rotated, Q * tau * Q.transpose()), 1e-12);
    }
  }
}

TEST(HyperelasticSmallStrain, NeoHookeanAndHenckyReduceToLinearElasticity) {
  const Mat3 G{{0.8, -0.3, 0.5}, {0.2, -0.6, 0.1}, {-0.4, 0.7, 0.3}};
  const Mat3 F = Mat3::Identity() + 1e-7 * G;
  const Mat3 expected = small_strain_stress(F, kLame);
  const double e_neo = rel(neo_hookean_kirchhoff(F, kLame), expected);
  const double e_hencky = rel(hencky_kirchhoff(F, kLame), expected);
  std::printf("[ small ] neo-Hookean %.2e  Hencky %.2e\n", e_neo, e_hencky);
  EXPECT_LT(e_neo, 1e-6);
  EXPECT_LT(e_hencky, 1e-6);
  // tau = P F^T differs from the small-strain sigma by O(|grad u|^2) relative: 1e-7 here
  EXPECT_LT(rel(linear_elastic_kirchhoff(F, kLame), expected), 1e-6);
  // the tangents at F = I all equal the small-strain modulus
  const Mat9 C = linear_elastic_response(Mat3::Identity(), kLame).dtau_dF;
  EXPECT_LT((neo_hookean_response(Mat3::Identity(), kLame).dtau_dF - C).norm(), 1e-12 * C.norm());
  EXPECT_LT((hencky_response(Mat3::Identity(), kLame).dtau_dF - C).norm(), 1e-12 * C.norm());
}

TEST(HyperelasticHencky, EnergyDerivativeIsFirstPiolaStress) {
  const Hencky hencky("h", 1000.0, kLame);
  for (const auto& c : tangent_cases()) {
    SCOPED_TRACE(c.name);
    const Mat3& F = c.F;
    const Mat3 P = hencky_kirchhoff(F, kLame) * F.inverse().transpose();
    if (P.norm() == 0.0) {
      EXPECT_DOUBLE_EQ(hencky.energy_density(F), 0.0);
      continue;
    }
    const double h = 1e-6 * std::max(1.0, F.cwiseAbs().maxCoeff());
    Mat3 fd;
    for (int k = 0; k < 3; ++k)
      for (int l = 0; l < 3; ++l) {
        Mat3 Fp = F, Fm = F;
        Fp(k, l) += h;
        Fm(k, l) -= h;
        fd(k, l) = (hencky.energy_density(Fp) - hencky.energy_density(Fm)) / (2.0 * h);
      }
    const double err = rel(fd, P);
    std::printf("[ psi ] %-58s rel. error %.2e\n", c.name.c_str(), err);
    EXPECT_LT(err, 1e-6);
  }
}

TEST(HyperelasticHencky, PureDilatationIsExact) {
  // Exact up to the rounding of b = F F^T: the log strain is off by a few ulps of 1 at most, so
  // the check is absolute in e (1e-15) and relative in tau (1e-14) - not relative to ln(s) alone,
  // which for s = 1 + 1e-6 would amplify the ulp of s^2 by 1e6.
  const double bulk3 = 3.0 * kLame.lambda + 2.0 * kLame.mu;
  for (double s : {1.2, 0.7, 2.5, 1.0 + 1e-6}) {
    SCOPED_TRACE(s);
    const Mat3 expected = bulk3 * std::log(s) * Mat3::Identity();
    const double tol = 1e-14 * expected.norm() + 1e-15 * bulk3;
    EXPECT_LT((hencky_kirchhoff(s * Mat3::Identity(), kLame) - expected).norm(), tol);
    // and after a rotation (F = s Q, b = s^2 I up to round-off)
    EXPECT_LT((hencky_kirchhoff(s * kQ1, kLame) - expected).norm(), 1e3 * tol);
  }
}

TEST(HyperelasticHencky, MaterialUpdateStressIsKirchhoffOverJ) {
  MaterialSpec spec;
  spec.name = "soil";
  spec.model = MaterialModel::Hencky;
  spec.density = 1800;
  spec.youngs_modulus = 2.0e7;
  spec.poisson_ratio = 0.3;
  const auto material = make_material(spec);
  ASSERT_NE(dynamic_cast<const Hencky*>(material.get()), nullptr);

  const std::vector<Mat3> F = {embedded<2>(Mat2{{1.3, 0.2}, {-0.1, 0.8}}), Mat3::Identity(),
                               embedded<2>(rotation2(0.5) * Mat2{{3.0, 0.0}, {0.0, 0.3}})};
  const std::vector<Index> ids = {0, 2};
  std::vector<Mat3> sigma(F.size(), Mat3::Constant(-1.0));
  material->update_stress(ids, F, sigma);
  for (Index p : ids) {
    const Mat3& F3 = F[static_cast<std::size_t>(p)];
    EXPECT_LT(rel(sigma[static_cast<std::size_t>(p)],
                  hencky_kirchhoff(F3, material->lame()) / F3.determinant()),
              1e-15);
  }
  EXPECT_EQ(sigma[1], Mat3::Constant(-1.0)); // not in ids: untouched

  const std::vector<Mat3> inverted = {embedded<2>(Mat2{{-1.0, 0.0}, {0.0, 1.0}})};
  const std::vector<Index> one = {0};
  std::vector<Mat3> out(1);
  EXPECT_THROW(material->update_stress(one, inverted, out), NumericalError);
  EXPECT_TRUE(std::isnan(dynamic_cast<const Hencky&>(*material).energy_density(inverted[0])));
  EXPECT_THROW(hencky_response(inverted[0], material->lame()), NumericalError);
}

TEST(HyperelasticMaterials, ClassStressesShareTheKirchhoffFunctions) {
  const LinearElastic linear("l", 1000.0, kLame);
  const NeoHookean neo("n", 1000.0, kLame);
  for (const auto& c : tangent_cases()) {
    SCOPED_TRACE(c.name);
    const double J = c.F.determinant();
    EXPECT_LT((linear.stress(c.F) - linear_elastic_kirchhoff(c.F, kLame) / J).norm(),
              1e-15 * (1.0 + linear.stress(c.F).norm()));
    EXPECT_LT((neo.stress(c.F) - neo_hookean_kirchhoff(c.F, kLame) / J).norm(),
              1e-15 * (1.0 + neo.stress(c.F).norm()));
  }
  EXPECT_THROW(neo.stress(diag(-1.0, 1.0, 1.0)), NumericalError);
}

// ---- principal-space calculus ---------------------------------------------------------------

namespace {

/// dT/dA of a tensor function T(A) by central differences on symmetric increments
/// (each perturbation of A_kl also perturbs A_lk by the same amount, half each off-diagonal).
Mat9 symmetric_fd(const std::function<Mat3(const Mat3&)>& T, const Mat3& A, double h) {
  Mat9 fd;
  for (int k = 0; k < 3; ++k)
    for (int l = 0; l < 3; ++l) {
      Mat3 dA = Mat3::Zero();
      dA(k, l) += 0.5 * h;
      dA(l, k) += 0.5 * h;
      fd.col(flat_index(k, l)) = flatten(T(A + dA) - T(A - dA)) / (2.0 * h);
    }
  return fd;
}

/// The isotropic tensor function T(A) = tr(A) A: f_a = x_a sum(x), D_ab = d_ab sum(x) + x_a
/// (a non-diagonal principal derivative, as in a principal-space return map).
Mat3 trace_times(const Mat3& A) {
  return A.trace() * A;
}

Mat9 trace_times_derivative(const Mat3& A) {
  const SpectralDecomposition s = spectral_decomposition(A);
  const Vec3 f = s.values * s.values.sum();
  Mat3 D = Mat3::Identity() * s.values.sum();
  for (int a = 0; a < 3; ++a)
    D.row(a) += Vec3::Constant(s.values(a)).transpose();
  return isotropic_function_derivative(s, f, D);
}

std::vector<NamedF> symmetric_cases() {
  return {{"distinct", kQ1 * diag(2.0, 1.0, 0.5) * kQ1.transpose()},
          {"double", kQ1 * diag(2.0, 2.0, 0.5) * kQ1.transpose()},
          {"nearly double (gap 1e-9)", kQ1 * diag(2.0, 2.0 + 2e-9, 0.5) * kQ1.transpose()},
          {"nearly double (gap 1e-6)", kQ1 * diag(2.0, 2.0 + 2e-6, 0.5) * kQ1.transpose()},
          {"triple", 1.5 * Mat3::Identity()},
          {"identity", Mat3::Identity()}};
}

} // namespace

TEST(HyperelasticPrincipalSpace, IdentityFunctionGivesSymmetricIdentity) {
  for (const auto& c : symmetric_cases()) {
    SCOPED_TRACE(c.name);
    const SpectralDecomposition s = spectral_decomposition(c.F);
    EXPECT_LT((from_principal(s, s.values) - c.F).norm(), 1e-14 * c.F.norm());
    const Mat9 L = isotropic_function_derivative(s, s.values, Mat3::Identity());
    Mat9 sym = Mat9::Zero();
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        sym(flat_index(i, j), flat_index(i, j)) += 0.5;
        sym(flat_index(i, j), flat_index(j, i)) += 0.5;
      }
    EXPECT_LT((L - sym).norm(), 1e-13);
  }
}

TEST(HyperelasticPrincipalSpace, NonDiagonalPrincipalDerivativeMatchesAnalytic) {
  for (const auto& c : symmetric_cases()) {
    SCOPED_TRACE(c.name);
    const Mat3& A = c.F;
    // d(tr(A) A) = tr(dA) A + tr(A) dA, on symmetric dA
    Mat9 exact = Mat9::Zero();
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        for (int k = 0; k < 3; ++k)
          exact(flat_index(i, j), flat_index(k, k)) += A(i, j);
        exact(flat_index(i, j), flat_index(i, j)) += 0.5 * A.trace();
        exact(flat_index(i, j), flat_index(j, i)) += 0.5 * A.trace();
      }
    const Mat9 L = trace_times_derivative(A);
    const double err = (L - exact).norm() / exact.norm();
    std::printf("[ iso ] tr(A) A, %-26s rel. error %.2e\n", c.name.c_str(), err);
    EXPECT_LT(err, 1e-8);
    EXPECT_LT((symmetric_fd(trace_times, A, 1e-6) - exact).norm() / exact.norm(), 1e-8);
  }
}

TEST(HyperelasticPrincipalSpace, GenericDividedDifferencesMatchFiniteDifferences) {
  // A^3 and ln(A) through the generic (f, df/dx) path, including (nearly) repeated eigenvalues
  const auto cube = [](const Mat3& A) { return Mat3(A * A * A); };
  const auto log_of = [](const Mat3& A) {
    const SpectralDecomposition s = spectral_decomposition(A);
    return from_principal(s, s.values.array().log().matrix());
  };
  for (const auto& c : symmetric_cases()) {
    SCOPED_TRACE(c.name);
    const SpectralDecomposition s = spectral_decomposition(c.F);
    const Vec3 x = s.values;
    const Mat9 Lcube = isotropic_function_derivative(
        s, x.array().cube().matrix(), Mat3(Vec3(3.0 * x.array().square()).asDiagonal()));
    const Mat9 Llog = isotropic_function_derivative(s, x.array().log().matrix(),
                                                    Mat3(Vec3(x.array().inverse()).asDiagonal()));
    const Mat9 fd_cube = symmetric_fd(cube, c.F, 1e-6);
    const Mat9 fd_log = symmetric_fd(log_of, c.F, 1e-6);
    const double e_cube = (Lcube - fd_cube).norm() / Lcube.norm();
    const double e_log = (Llog - fd_log).norm() / Llog.norm();
    std::printf("[ iso ] A^3 %.2e, ln A %.2e  %s\n", e_cube, e_log, c.name.c_str());
    EXPECT_LT(e_cube, 1e-7);
    EXPECT_LT(e_log, 1e-7);
  }
}

TEST(HyperelasticPrincipalSpace, LeftCauchyGreenDerivative) {
  const Mat3 F = kQ1 * diag(1.3, 0.8, 1.1) * kQ2;
  const Mat9 D = left_cauchy_green_derivative(F);
  const Mat3 dF{{0.3, -0.2, 0.1}, {0.5, 0.05, -0.4}, {0.0, 0.2, 0.7}};
  // b is quadratic in F: the directional derivative is exact
  EXPECT_LT((unflatten(D * flatten(dF)) - (dF * F.transpose() + F * dF.transpose())).norm(), 1e-14);
  EXPECT_EQ(unflatten(flatten(F)), F);
  EXPECT_EQ(flatten(F)(flat_index(0, 1)), F(0, 1));
}
