#pragma once
// GIMP: the grid's hat function averaged over a particle domain of half-width lp,
//     N(r) = 1/(2 lp) int_{r-lp}^{r+lp} hat(s) ds,   r = x_p - x_i.
//
//  * GimpShape: uGIMP (Bardenhagen & Kober 2004), the domain keeps its initial size
//    (lp <= h/2, three nodes per direction); the closed-form branches below.
//  * CpGimpShape: the domain follows the point's stretch (shape/deformed_domain.hpp), so lp
//    changes every step and may reach h (four nodes per direction). Its value is the same
//    average written once for any lp through the hat's antiderivative,
//        N(r) = (A(r + lp) - A(r - lp)) / (2 lp),  dN/dr = (hat(r + lp) - hat(r - lp)) / (2 lp),
//    exact whether or not the domain straddles a node.
#include "talus/core/types.hpp"

#include <algorithm>
#include <cmath>

namespace talus {

struct GimpShape {
  static constexpr int kWidth = 3;
  static constexpr bool kDomainFollowsStretch = false;
  static constexpr const char* kName = "gimp";
  /// x: particle coordinate relative to the grid origin; cells: the grid's cells on this axis.
  static Index start(double x, double h, double lp, Index /*cells*/) {
    return static_cast<Index>(std::floor((x - lp) / h));
  }
  /// Value and derivative of the uGIMP function for distance r = x_p - x_i.
  static void value(double r, double h, double lp, double& N, double& dN) {
    value(r, h, lp, 1.0 / h, 1.0 / (h * lp), N, dN);
  }
  static void eval(double x, double h, double lp, Index /*cells*/, Index start, double* N,
                   double* dN) {
    // The reciprocals once per point and axis: divisions dominated the map's update.
    const double inv_h = 1.0 / h, inv_hlp = 1.0 / (h * lp);
    for (int a = 0; a < kWidth; ++a)
      value(x - h * static_cast<double>(start + a), h, lp, inv_h, inv_hlp, N[a], dN[a]);
  }

private:
  static void value(double r, double h, double lp, double inv_h, double inv_hlp, double& N,
                    double& dN) {
    const double ar = std::abs(r);
    const double sign = r >= 0 ? 1.0 : -1.0;
    if (ar < lp) {
      N = 1.0 - 0.5 * (r * r + lp * lp) * inv_hlp;
      dN = -r * inv_hlp;
    } else if (ar < h - lp) {
      N = 1.0 - ar * inv_h;
      dN = -sign * inv_h;
    } else if (ar < h + lp) {
      const double s = h + lp - ar;
      N = 0.25 * s * s * inv_hlp;
      dN = -0.5 * sign * s * inv_hlp;
    } else {
      N = 0.0;
      dN = 0.0;
    }
  }
};

struct CpGimpShape {
  static constexpr int kWidth = 4;
  static constexpr bool kDomainFollowsStretch = true;
  static constexpr const char* kName = "cpgimp";
  /// The widest domain the four-node stencil holds.
  static constexpr double kMaxHalfWidthInCells = 1.0;

  /// The first of four nodes; near the upper face the stencil is held inside the ghost layer
  /// (the node it drops carries no weight: x <= cells h and lp <= h).
  static Index start(double x, double h, double lp, Index cells) {
    return std::min(static_cast<Index>(std::floor((x - lp) / h)), cells + 1 - (kWidth - 1));
  }
  static void value(double r, double h, double lp, double& N, double& dN) {
    N = (antiderivative(r + lp, h) - antiderivative(r - lp, h)) / (2.0 * lp);
    dN = (hat(r + lp, h) - hat(r - lp, h)) / (2.0 * lp);
  }
  static void eval(double x, double h, double lp, Index /*cells*/, Index start, double* N,
                   double* dN) {
    for (int a = 0; a < kWidth; ++a)
      value(x - h * static_cast<double>(start + a), h, lp, N[a], dN[a]);
  }

private:
  static double hat(double s, double h) { return std::max(0.0, 1.0 - std::abs(s) / h); }
  /// int_0^s hat.
  static double antiderivative(double s, double h) {
    const double a = std::min(std::abs(s), h);
    return std::copysign(a - a * a / (2.0 * h), s);
  }
};

} // namespace talus
