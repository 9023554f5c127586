// Bishop's simplified method, the independent reference of the 3D slope verification.
#include "../../src/verify/slope_limit_equilibrium.hpp"

#include <cmath>
#include <gtest/gtest.h>

namespace {

using talus::verify_cases::bishop_circle;
using talus::verify_cases::bishop_surface;
using talus::verify_cases::critical_circle;
using talus::verify_cases::critical_surface;
using talus::verify_cases::SlipSurface;
using talus::verify_cases::SlopeSection;

// Griffiths & Lane's (1999) example 1: H = 10 m, 2:1, gamma = 20 kN/m3, c' = 10 kPa,
// phi' = 20 deg, firm base at the toe.
SlopeSection griffiths_lane(double tan_phi = std::tan(20 * std::acos(-1.0) / 180)) {
  SlopeSection s;
  s.surface_x = {12, 32};
  s.surface_y = {10, 0};
  s.unit_weight = 2e4;
  s.cohesion = 1e4;
  s.tan_phi = tan_phi;
  return s;
}

// Bishop & Morgenstern's charts give 1.38 for c'/(gamma H) = 0.05, phi' = 20 deg, 2:1, D = 1
// (quoted by Griffiths & Lane): within 1 % (the charts' two digits and the circle search).
TEST(SlopeLimitEquilibrium, BishopMatchesTheChartsInPlaneStrain) {
  EXPECT_NEAR(critical_circle(griffiths_lane(), 0, 0).factor, 1.38, 0.014);
}

// With phi' = 0 Bishop's method is exact for a circle: F = c R L / M, with L the arc length
// under the slip mass and M the weight's moment. A circle through the crest's corner region
// checked against that closed form, computed by fine quadrature of the same geometry.
TEST(SlopeLimitEquilibrium, CohesiveCircleIsTheClosedForm) {
  const SlopeSection s = griffiths_lane(0.0);
  const double cx = 28, cy = 24, r = 24; // tangent to the base
  // Arc length and moment of the slip mass by fine quadrature.
  double arc = 0, moment = 0;
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    const double x = cx - r + (i + 0.5) * 2 * r / n;
    const double surface = x <= 12 ? 10 : (x >= 32 ? 0 : 10 - (x - 12) / 2);
    const double base = cy - std::sqrt(r * r - (x - cx) * (x - cx));
    if (surface > base) {
      arc += 2 * r / n * r / std::sqrt(r * r - (x - cx) * (x - cx));
      moment += s.unit_weight * (surface - base) * 2 * r / n * (cx - x);
    }
  }
  const double exact = s.cohesion * r * arc / moment;
  // 200 slices: measured 6.8e-4 (the partial slices where the arc leaves the surface). Broken
  // on purpose (m_alpha = 1, the cohesion on the slice width instead of the base) it is -12 %.
  EXPECT_NEAR(bishop_circle(s, cx, cy, r, 0, 0).factor / exact, 1.0, 2e-3);
}

// End walls add resistance that fades with the width and grows with the end planes' stress.
TEST(SlopeLimitEquilibrium, EndPlanesRaiseTheFactorAndFadeWithWidth) {
  const SlopeSection s = griffiths_lane();
  const double plane = critical_circle(s, 0, 0).factor;
  double previous = 1e9;
  for (double width : {10.0, 20.0, 40.0, 80.0, 1e5}) {
    const double f = critical_circle(s, width, 0.43).factor;
    EXPECT_GT(f, plane);
    EXPECT_LT(f, previous);
    previous = f;
  }
  EXPECT_NEAR(previous, plane, 1e-3);
  EXPECT_LT(critical_circle(s, 20, 0).factor, critical_circle(s, 20, 0.43).factor);
  EXPECT_LT(critical_circle(s, 20, 0.43).factor, critical_circle(s, 20, 1).factor);
}

// Hungr's columns on a surface of revolution with an infinite length are the cylinder: the
// same factor as the slices of the circle with its two end planes (one code path checked by
// the other, to the fixed point's tolerance).
TEST(SlopeLimitEquilibrium, InfinitelyLongSurfaceIsTheCylinderWithEndPlanes) {
  const SlopeSection s = griffiths_lane();
  const double cx = 28, cy = 23, r = 23;
  const SlipSurface cylinder = bishop_surface(s, {0, cx, cy, r}, 20, 0.43);
  EXPECT_NEAR(cylinder.factor / bishop_circle(s, cx, cy, r, 20, 0.43).factor, 1.0, 1e-9);
}

// With phi' = 0 the method is exact for any surface of revolution: F = c' (integral of r dA)
// / M, the shear's moment about the axis over the weight's. An ellipsoid (p = 2) that misses
// the walls, checked against that closed form by an independent quadrature of the surface
// y_b(x, z) = cy - sqrt(r(z)^2 - (x - cx)^2): dA = sqrt(1 + y_b,x^2 + y_b,z^2) dx dz.
TEST(SlopeLimitEquilibrium, CohesiveEllipsoidIsTheClosedForm) {
  const SlopeSection s = griffiths_lane(0.0);
  const double width = 40, cx = 28, cy = 24, big_r = 24, length = 30;
  double shear_moment = 0, weight_moment = 0;
  const int n = 2000;
  for (int k = 0; k < n; ++k) {
    const double z = width / 2 + (k + 0.5 - n / 2.0) * length / n;
    const double zeta = 2 * (z - width / 2) / length;
    const double r = big_r * std::sqrt(1 - zeta * zeta);
    const double r_z = -big_r * big_r * 4 * (z - width / 2) / (length * length) / r; // r'(z)
    for (int i = 0; i < n; ++i) {
      const double x = cx - r + (i + 0.5) * 2 * r / n;
      const double depth = std::sqrt(r * r - (x - cx) * (x - cx));
      const double surface = x <= 12 ? 10 : (x >= 32 ? 0 : 10 - (x - 12) / 2);
      const double height = surface - (cy - depth);
      if (height <= 0)
        continue;
      const double plan = 2 * r / n * length / n;
      const double slope_x = (x - cx) / depth, slope_z = r * r_z / depth;
      shear_moment += s.cohesion * r * std::sqrt(1 + slope_x * slope_x + slope_z * slope_z) * plan;
      weight_moment += s.unit_weight * height * plan * (cx - x);
    }
  }
  const SlipSurface ellipsoid = bishop_surface(s, {0, cx, cy, big_r, length, 2}, width, 0);
  // Measured 3.1e-4 (128 strips, 200 columns; the quadrature itself moves by 2e-5 from 2000
  // to 4000 points a side), so 1e-3; broken on purpose (the flanks' steepness dropped from the
  // base area) it is -9.9 %.
  EXPECT_NEAR(ellipsoid.factor / (shear_moment / weight_moment), 1.0, 1e-3);
}

// Surfaces that curve away from the walls shed most of the end planes' resistance: the least
// factor over them lies well below the cylinder's (measured 0.954 of it) and above plane
// strain's, and the end planes' stress hardly matters any more (measured 1.2 % from K = 0 to
// K = 1, against the cylinder's 10 %). Broken on purpose (the end planes always at the full
// radius R): the curved minimum is the cylinder and K moves it by 10 %; both checks fail.
TEST(SlopeLimitEquilibrium, CurvedEndsLowerTheEndWallsRise) {
  const SlopeSection s = griffiths_lane();
  const double plane = critical_circle(s, 0, 0).factor;
  const double curved = critical_surface(s, 20, 0.43, {2, 4, 10}).factor;
  EXPECT_LT(curved / critical_circle(s, 20, 0.43).factor, 0.98);
  EXPECT_GT(curved / plane, 1.05);
  const double k0 = critical_surface(s, 20, 0, {2, 4, 10}).factor;
  const double k1 = critical_surface(s, 20, 1, {2, 4, 10}).factor;
  EXPECT_LT(k0, k1);
  EXPECT_LT(k1 / k0, 1.03);
}

} // namespace
