// CPDI's weights against independent references: the corners' hats averaged by brute force over
// the grid, and the gradient by the divergence theorem over the parallelogram's edges (the
// multilinear interpolant is linear along each edge), for a sheared and stretched voxel whose
// bounding box is not a tensor-product stencil; the voxel wider than the stencil is refused.
#include "talus/shape/cpdi.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>

using namespace talus;

namespace {

constexpr double kH = 0.5;

/// The bilinear hat of node (i, j) at x.
double hat(const Vec2& x, Index i, Index j) {
  return std::max(0.0, 1.0 - std::abs(x[0] / kH - static_cast<double>(i))) *
         std::max(0.0, 1.0 - std::abs(x[1] / kH - static_cast<double>(j)));
}

} // namespace

TEST(Cpdi, WeightsAreTheCornersHatsAndGradientsTheBoundaryIntegral) {
  const Vec2 x(2.3, 1.7), lp0(kH / 4, kH / 4);
  const Mat2 F = (Mat2() << 1.4, 1.5, 0.2, 0.8).finished(); // sheared, stretched, det 0.82
  CpdiShape::Weights<2> w;
  CpdiShape::fill<2>(0, x, F, lp0, kH, {10, 10}, w);
  const Mat2 J = F * lp0.asDiagonal();
  // Corners counter-clockwise in xi: (-1,-1), (1,-1), (1,1), (-1,1).
  const std::array<Vec2, 4> xi = {Vec2(-1, -1), Vec2(1, -1), Vec2(1, 1), Vec2(-1, 1)};
  std::array<Vec2, 4> corner;
  for (int c = 0; c < 4; ++c)
    corner[c] = x + J * xi[c];
  const double area = 4 * J.determinant();
  double sum = 0;
  Index lowest = 100, highest = -100;
  for (int k = 0; k < 16; ++k) {
    const Index i = w.start[0] + k % 4, j = w.start[1] + k / 4;
    double expected = 0;
    Vec2 boundary = Vec2::Zero();
    for (int c = 0; c < 4; ++c) {
      expected += hat(corner[c], i, j) / 4;
      const Vec2 a = corner[c], b = corner[(c + 1) % 4];
      const Vec2 normal_length(b[1] - a[1], a[0] - b[0]); // outward for counter-clockwise
      boundary += normal_length * (hat(a, i, j) + hat(b, i, j)) / 2;
    }
    EXPECT_NEAR(w.w[k], expected, 1e-15) << "node " << i << ", " << j;
    EXPECT_NEAR((w.grad[k] - boundary / area).norm(), 0.0, 1e-13) << "node " << i << ", " << j;
    sum += w.w[k];
    if (w.w[k] > 0) {
      lowest = std::min(lowest, i);
      highest = std::max(highest, i);
    }
  }
  EXPECT_NEAR(sum, 1.0, 1e-15);
  // The sheared voxel's corners lie in three cells along x: four columns of nodes carry
  // weight, more than a three-node stencil holds.
  EXPECT_EQ(highest - lowest, 3);
}

TEST(Cpdi, AVoxelWiderThanTheStencilIsANumericalError) {
  const Mat2 F = (Mat2() << 3.0, 2.0, 0.0, 1.0).finished(); // x half-extent 5 lp0 = 1.25 h
  CpdiShape::Weights<2> w;
  try {
    CpdiShape::fill<2>(7, Vec2(2.3, 1.7), F, Vec2(kH / 4, kH / 4), kH, {10, 10}, w);
    FAIL() << "expected a NumericalError";
  } catch (const NumericalError& e) {
    EXPECT_NE(std::string(e.what()).find("particle 7's cpdi domain"), std::string::npos)
        << e.what();
  }
}

// At the grid's faces the corners' hats stay within the ghost layer: a voxel reaching a cell
// beyond the upper face (x up to (cells + 1) h) keeps all its weight on existing nodes.
TEST(Cpdi, VoxelsReachingBeyondAFaceStayInTheGhostLayer) {
  const Vec2 x(5.0, 0.0), lp0(kH / 2, kH / 2); // on the grid's corner node (10, 0)
  const Mat2 F = Vec2(2.0, 2.0).asDiagonal();  // half-extent exactly h
  CpdiShape::Weights<2> w;
  CpdiShape::fill<2>(0, x, F, lp0, kH, {10, 10}, w);
  EXPECT_LE(w.start[0] + 3, 11);
  EXPECT_GE(w.start[1], -1);
  double sum = 0;
  Vec2 first = Vec2::Zero();
  for (int k = 0; k < 16; ++k) {
    sum += w.w[k];
    first += w.w[k] * kH * Vec2(w.start[0] + k % 4, w.start[1] + k / 4);
  }
  EXPECT_NEAR(sum, 1.0, 1e-15);
  EXPECT_NEAR((first - x).norm(), 0.0, 1e-14);
}
