// Shape functions: partition of unity, zero-sum gradients, linear reproduction, and uGIMP
// values computed by hand (the hat function averaged over the particle domain).
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
    const Index s = Shape::start(x, h, lp);
    double N[Shape::kWidth], dN[Shape::kWidth];
    Shape::eval(x, h, lp, s, N, dN);
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
  LinearShape::eval(2.0, 1.0, 0.0, LinearShape::start(2.0, 1.0, 0.0), N, dN);
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
  const Index s = GimpShape::start(x, h, lp);
  ASSERT_EQ(s, -1);
  double N[3], dN[3];
  GimpShape::eval(x, h, lp, s, N, dN);
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
