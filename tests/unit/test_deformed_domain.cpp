// cpGIMP's domain: the diagonal of the right stretch tensor U of F = R U, against U built
// independently (the square root of C through its eigen-decomposition), free of rotation, and
// exact for stretches along the axes.
#include "talus/shape/deformed_domain.hpp"
#include "talus/shape/shape_functions.hpp"

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>
#include <random>

using namespace talus;

namespace {

template <int Dim> Mat<Dim> stretch_reference(const Mat<Dim>& F) {
  const Eigen::SelfAdjointEigenSolver<Mat<Dim>> eig(F.transpose() * F);
  return eig.eigenvectors() * eig.eigenvalues().cwiseSqrt().asDiagonal() *
         eig.eigenvectors().transpose();
}

template <int Dim> Mat<Dim> rotation(double angle) {
  Mat<Dim> R = Mat<Dim>::Identity();
  R(0, 0) = R(1, 1) = std::cos(angle);
  R(1, 0) = std::sin(angle);
  R(0, 1) = -R(1, 0);
  return R;
}

template <int Dim> void check_random_deformations() {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-0.6, 0.6), a(-3.0, 3.0);
  for (int trial = 0; trial < 200; ++trial) {
    Mat<Dim> F = Mat<Dim>::Identity();
    for (int i = 0; i < Dim; ++i)
      for (int j = 0; j < Dim; ++j)
        F(i, j) += u(rng);
    if (F.determinant() <= 0.05)
      continue;
    const Vec<Dim> expected = stretch_reference<Dim>(F).diagonal();
    EXPECT_LT((right_stretch_diagonal<Dim>(F) - expected).norm(), 1e-12) << F;
    // A rigid rotation applied after the deformation leaves U alone.
    const Mat<Dim> RF = rotation<Dim>(a(rng)) * F;
    EXPECT_LT((right_stretch_diagonal<Dim>(RF) - expected).norm(), 1e-12) << F;
  }
}

} // namespace

TEST(DeformedDomain, RightStretchDiagonalIn2D) {
  check_random_deformations<2>();
}
TEST(DeformedDomain, RightStretchDiagonalIn3D) {
  check_random_deformations<3>();
}

// A rotation by 90 degrees keeps the domain (F's diagonal would give it zero width); a
// stretch along the axes scales it exactly.
TEST(DeformedDomain, RotationKeepsAndAxialStretchScalesTheDomain) {
  const Mat2 R = rotation<2>(std::acos(-1.0) / 2);
  EXPECT_LT((right_stretch_diagonal<2>(R) - Vec2::Ones()).norm(), 1e-15);
  const Mat2 S = Vec2(0.2, 3.0).asDiagonal();
  EXPECT_LT((right_stretch_diagonal<2>(R * S) - Vec2(0.2, 3.0)).norm(), 1e-14);
  const Mat3 S3 = Vec3(0.2, 3.0, 1.5).asDiagonal();
  EXPECT_LT((right_stretch_diagonal<3>(rotation<3>(0.3) * S3) - Vec3(0.2, 3.0, 1.5)).norm(), 1e-13);
}

TEST(DeformedDomain, OnlyCpGimpStretchesTheDomain) {
  Particles<2> P;
  P.resize(1);
  P.half_size0[0] = Vec2(0.1, 0.2);
  P.F[0].topLeftCorner<2, 2>() = Vec2(0.5, 2.0).asDiagonal();
  EXPECT_EQ((domain_half_widths<2, CpGimpShape>(P, 0)), Vec2(0.05, 0.4));
  EXPECT_EQ((domain_half_widths<2, GimpShape>(P, 0)), Vec2(0.1, 0.2));
}
