// Shape functions: partition of unity, zero-sum gradients, linear reproduction, slopes against
// differences, values computed by hand (uGIMP, cpGIMP's wide domain, the splines on a node),
// and the B-splines' interpolation at the grid faces and smoothness across cell faces.
#include "talus/shape/shape_functions.hpp"

#include <gtest/gtest.h>
#include <numeric>
#include <random>

using namespace talus;

namespace {

template <class Shape> void check_partition_and_reproduction(double h, double lp) {
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> pos(lp + 1e-3, 10.0 * h);
  for (int trial = 0; trial < 2000; ++trial) {
    const double x = pos(rng);
    const Index s = Shape::start(x, h, lp, 1000);
    double N[Shape::kWidth], dN[Shape::kWidth];
    Shape::eval(x, h, lp, 1000, s, N, dN);
    double sum = 0, dsum = 0, first = 0, dfirst = 0;
    for (int a = 0; a < Shape::kWidth; ++a) {
      EXPECT_GE(N[a], -1e-15);
      const double xi = h * static_cast<double>(s + a);
      sum += N[a];
      dsum += dN[a];
      first += N[a] * xi;
      dfirst += dN[a] * xi;
    }
    EXPECT_NEAR(sum, 1.0, 1e-14) << "x = " << x;
    EXPECT_NEAR(dsum, 0.0, 1e-12 / h) << "x = " << x;
    EXPECT_NEAR(first, x, 1e-13 * 10 * h) << "linear field reproduced, x = " << x;
    EXPECT_NEAR(dfirst, 1.0, 1e-12) << "its gradient reproduced, x = " << x;
  }
}

} // namespace

TEST(ShapeFunctions, LinearPartitionOfUnityAndReproduction) {
  check_partition_and_reproduction<LinearShape>(0.37, 0.0);
}

TEST(ShapeFunctions, GimpPartitionOfUnityAndReproduction) {
  check_partition_and_reproduction<GimpShape>(0.37, 0.37 / 4);
  check_partition_and_reproduction<GimpShape>(1.0, 0.5); // widest allowed domain
}

TEST(ShapeFunctions, LinearOnANodeHasZeroSumGradient) {
  double N[2], dN[2];
  LinearShape::eval(2.0, 1.0, 0.0, 10, LinearShape::start(2.0, 1.0, 0.0, 10), N, dN);
  EXPECT_DOUBLE_EQ(N[0], 1.0);
  EXPECT_DOUBLE_EQ(N[1], 0.0);
  EXPECT_DOUBLE_EQ(dN[0] + dN[1], 0.0);
}

// h = 1, lp = 0.25, particle at x = 0.1 (nodes -1, 0, 1):
//   node  0: average of 1 - |s| over s in [-0.15, 0.35] = 0.4275 / 0.5 = 0.855, slope -0.4
//   node  1: (h + lp - |r|)^2 / (4 h lp) with r = -0.9: 0.35^2 = 0.1225, slope +0.7
//   node -1: r = 1.1: 0.15^2 = 0.0225, slope -0.3
TEST(ShapeFunctions, GimpHandComputedValuesAcrossCells) {
  const double h = 1.0, lp = 0.25, x = 0.1;
  const Index s = GimpShape::start(x, h, lp, 1000);
  ASSERT_EQ(s, -1);
  double N[3], dN[3];
  GimpShape::eval(x, h, lp, 1000, s, N, dN);
  EXPECT_NEAR(N[0], 0.0225, 1e-15);
  EXPECT_NEAR(N[1], 0.855, 1e-15);
  EXPECT_NEAR(N[2], 0.1225, 1e-15);
  EXPECT_NEAR(dN[0], -0.3, 1e-15);
  EXPECT_NEAR(dN[1], -0.4, 1e-15);
  EXPECT_NEAR(dN[2], 0.7, 1e-15);
}

// The three GIMP branches meet continuously: at r = lp and r = h - lp, and vanish at h + lp.
TEST(ShapeFunctions, GimpBranchesAreContinuous) {
  const double h = 1.0, lp = 0.25, d = 1e-12;
  for (double r : {lp, h - lp, h + lp}) {
    double a, da, b, db;
    GimpShape::value(r - d, h, lp, a, da);
    GimpShape::value(r + d, h, lp, b, db);
    EXPECT_NEAR(a, b, 1e-11) << "r = " << r;
    EXPECT_NEAR(da, db, 1e-10) << "r = " << r;
  }
  double n, dn;
  GimpShape::value(h + lp, h, lp, n, dn);
  EXPECT_EQ(n, 0.0);
  GimpShape::value(0.0, h, lp, n, dn);
  EXPECT_DOUBLE_EQ(n, 1.0 - lp / (2.0 * h)); // 1 - lp^2 / (2 h lp)
  EXPECT_DOUBLE_EQ(dn, 0.0);
}

namespace {

/// Partition of unity, zero-sum gradients, linear reproduction and non-negative values on
/// [0, cells h], faces included (B-splines are modified there), with values and slopes of
/// the nodes start .. start + W - 1 and the stencil inside the ghost layer.
template <class Shape> void check_on_bounded_axis(double h, double lp, Index cells) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> pos(0.0, h * static_cast<double>(cells));
  std::vector<double> xs = {0.0, h * static_cast<double>(cells), 0.5 * h, 1e-14};
  for (int trial = 0; trial < 3000; ++trial)
    xs.push_back(pos(rng));
  for (const double x : xs) {
    const Index s = Shape::start(x, h, lp, cells);
    ASSERT_GE(s, -1);
    ASSERT_LE(s + Shape::kWidth - 1, cells + 1);
    double N[Shape::kWidth], dN[Shape::kWidth];
    Shape::eval(x, h, lp, cells, s, N, dN);
    double sum = 0, dsum = 0, first = 0, dfirst = 0;
    for (int a = 0; a < Shape::kWidth; ++a) {
      EXPECT_GE(N[a], -1e-15) << "x = " << x;
      const double xi = h * static_cast<double>(s + a);
      sum += N[a];
      dsum += dN[a];
      first += N[a] * xi;
      dfirst += dN[a] * xi;
    }
    EXPECT_NEAR(sum, 1.0, 1e-14) << "x = " << x;
    EXPECT_NEAR(dsum, 0.0, 1e-12 / h) << "x = " << x;
    EXPECT_NEAR(first, x, 1e-13 * static_cast<double>(cells) * h) << "x = " << x;
    EXPECT_NEAR(dfirst, 1.0, 1e-12) << "x = " << x;
  }
}

/// The slopes are the derivatives of the values (central differences, away from kinks).
template <class Shape> void check_slopes(double h, double lp, Index cells) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> pos(0.01 * h, (static_cast<double>(cells) - 0.01) * h);
  const double d = 1e-6 * h;
  for (int trial = 0; trial < 500; ++trial) {
    const double x = pos(rng);
    const Index s = Shape::start(x, h, lp, cells);
    double N[Shape::kWidth], dN[Shape::kWidth], Np[Shape::kWidth], Nm[Shape::kWidth],
        unused[Shape::kWidth];
    Shape::eval(x, h, lp, cells, s, N, dN);
    Shape::eval(x + d, h, lp, cells, s, Np, unused);
    Shape::eval(x - d, h, lp, cells, s, Nm, unused);
    for (int a = 0; a < Shape::kWidth; ++a)
      EXPECT_NEAR(dN[a], (Np[a] - Nm[a]) / (2 * d), 2e-4 / h) << "x = " << x << ", node " << a;
  }
}

} // namespace

TEST(ShapeFunctions, CpGimpPartitionOfUnityAndReproductionUpToACellWideDomain) {
  for (const double lp : {0.05, 0.25, 0.5, 0.75, 1.0})
    check_on_bounded_axis<CpGimpShape>(0.37, 0.37 * lp, 7);
}

TEST(ShapeFunctions, CpGimpSlopesAreTheDerivativesOfItsValues) {
  for (const double lp : {0.1, 0.5, 0.9})
    check_slopes<CpGimpShape>(0.37, 0.37 * lp, 7);
}

// For lp <= h/2 the antiderivative form is uGIMP's closed form, to round-off.
TEST(ShapeFunctions, CpGimpEqualsUGimpForDomainsUpToHalfACell) {
  const double h = 0.37;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> r(-2.0 * h, 2.0 * h), l(0.02 * h, 0.5 * h);
  for (int trial = 0; trial < 2000; ++trial) {
    const double rr = r(rng), lp = l(rng);
    double a, da, b, db;
    GimpShape::value(rr, h, lp, a, da);
    CpGimpShape::value(rr, h, lp, b, db);
    EXPECT_NEAR(a, b, 1e-14) << "r = " << rr << ", lp = " << lp;
    EXPECT_NEAR(da, db, 1e-13 / h) << "r = " << rr << ", lp = " << lp;
  }
}

// h = 1, lp = 0.75: a domain wider than half a cell straddles two nodes. At x = 0.5 the domain
// is [-0.25, 1.25] and the stencil nodes -1 .. 2; by hand, the hat's integral over it / 1.5:
//   node -1: int_{-0.25}^{0} -s ds = 0.03125          node 0: 0.21875 + 0.5 = 0.71875
//   nodes 1 and 2 the mirror images of nodes 0 and -1.
// Slopes (hat(r + lp) - hat(r - lp)) / (2 lp), r = x - x_i: node -1 (r = 1.5) -0.25 / 1.5,
// node 0 (r = 0.5) -0.75 / 1.5, and the mirror images.
TEST(ShapeFunctions, CpGimpHandComputedValuesOfAWideDomain) {
  const double h = 1.0, lp = 0.75, x = 0.5;
  const Index s = CpGimpShape::start(x, h, lp, 10);
  ASSERT_EQ(s, -1);
  double N[4], dN[4];
  CpGimpShape::eval(x, h, lp, 10, s, N, dN);
  EXPECT_NEAR(N[0], 0.03125 / 1.5, 1e-15);
  EXPECT_NEAR(N[1], 0.71875 / 1.5, 1e-15);
  EXPECT_NEAR(N[2], 0.71875 / 1.5, 1e-15);
  EXPECT_NEAR(N[3], 0.03125 / 1.5, 1e-15);
  EXPECT_NEAR(dN[0], -0.25 / 1.5, 1e-15);
  EXPECT_NEAR(dN[1], -0.75 / 1.5, 1e-15);
  EXPECT_NEAR(dN[2], 0.75 / 1.5, 1e-15);
  EXPECT_NEAR(dN[3], 0.25 / 1.5, 1e-15);
}

// ---- B-splines ----

TEST(ShapeFunctions, BSplinesPartitionOfUnityAndReproductionUpToTheFaces) {
  check_on_bounded_axis<QuadraticBSplineShape>(0.37, 0.0, 2);
  check_on_bounded_axis<QuadraticBSplineShape>(0.37, 0.0, 9);
  check_on_bounded_axis<CubicBSplineShape>(0.37, 0.0, 3);
  check_on_bounded_axis<CubicBSplineShape>(0.37, 0.0, 9);
}

TEST(ShapeFunctions, BSplineSlopesAreTheDerivativesOfTheirValues) {
  check_slopes<QuadraticBSplineShape>(0.37, 0.0, 9);
  check_slopes<CubicBSplineShape>(0.37, 0.0, 9);
}

// At a grid face only the face node's function is non-zero (and equal to one), so a roller or
// a fixed face holds the material on it.
template <class Shape> void check_face_condition(Index cells) {
  const double h = 0.5;
  for (const Index face : {Index{0}, cells}) {
    const double x = h * static_cast<double>(face);
    const Index s = Shape::start(x, h, 0.0, cells);
    double N[Shape::kWidth], dN[Shape::kWidth];
    Shape::eval(x, h, 0.0, cells, s, N, dN);
    for (int a = 0; a < Shape::kWidth; ++a)
      EXPECT_NEAR(N[a], s + a == face ? 1.0 : 0.0, 1e-15) << "face " << face << ", node " << a;
  }
}

TEST(ShapeFunctions, BSplinesAreInterpolatoryAtTheGridFaces) {
  check_face_condition<QuadraticBSplineShape>(6);
  check_face_condition<CubicBSplineShape>(6);
}

// Inside the grid the uniform splines: on a node 3/4, 1/8 (quadratic), 2/3, 1/6 (cubic).
TEST(ShapeFunctions, BSplineValuesOnAnInteriorNode) {
  double N[4], dN[4];
  QuadraticBSplineShape::eval(4.0, 1.0, 0.0, 9, QuadraticBSplineShape::start(4.0, 1.0, 0.0, 9), N,
                              dN);
  EXPECT_EQ(QuadraticBSplineShape::start(4.0, 1.0, 0.0, 9), 3);
  EXPECT_DOUBLE_EQ(N[0], 0.125);
  EXPECT_DOUBLE_EQ(N[1], 0.75);
  EXPECT_DOUBLE_EQ(N[2], 0.125);
  EXPECT_DOUBLE_EQ(dN[1], 0.0);
  CubicBSplineShape::eval(4.0, 1.0, 0.0, 9, CubicBSplineShape::start(4.0, 1.0, 0.0, 9), N, dN);
  EXPECT_EQ(CubicBSplineShape::start(4.0, 1.0, 0.0, 9), 3);
  EXPECT_DOUBLE_EQ(N[0], 1.0 / 6.0);
  EXPECT_DOUBLE_EQ(N[1], 2.0 / 3.0);
  EXPECT_DOUBLE_EQ(N[2], 1.0 / 6.0);
  EXPECT_DOUBLE_EQ(N[3], 0.0);
}

// The splines' gradients do not jump where a point crosses a cell face (the cause of the
// cell-crossing error of hats and uGIMP): C1 for quadratic, C2 for cubic, also next to a face.
template <class Shape> void check_gradient_continuity(Index cells) {
  const double h = 1.0, d = 1e-9;
  for (Index k = 1; k < cells; ++k) {
    const double x = h * static_cast<double>(k);
    for (Index node = 0; node <= cells; ++node) {
      double value[2], slope[2];
      for (int side = 0; side < 2; ++side) {
        const double xs = x + (side == 0 ? -d : d);
        const Index s = Shape::start(xs, h, 0.0, cells);
        double N[Shape::kWidth], dN[Shape::kWidth];
        Shape::eval(xs, h, 0.0, cells, s, N, dN);
        value[side] = slope[side] = 0.0;
        if (node >= s && node < s + Shape::kWidth) {
          value[side] = N[node - s];
          slope[side] = dN[node - s];
        }
      }
      EXPECT_NEAR(value[0], value[1], 1e-8) << "face " << k << ", node " << node;
      EXPECT_NEAR(slope[0], slope[1], 1e-8) << "face " << k << ", node " << node;
    }
  }
}

TEST(ShapeFunctions, BSplineGradientsAreContinuousAcrossCellFaces) {
  check_gradient_continuity<QuadraticBSplineShape>(6);
  check_gradient_continuity<CubicBSplineShape>(6);
}
