#pragma once
// Quadratic and cubic B-splines on the uniform grid (Steffen, Kirby & Berzins 2008), one
// function per node, centred on it: N_i(x) = B((x - x_i) / h) with support 3h (quadratic) or
// 4h (cubic). They are C1 (C2) across cell faces, so a point crossing a cell sees no jump in
// its gradient: the cell-crossing error of linear hats and uGIMP is gone at its root.
//
// Boundary modification at the grid's faces. Inside the grid the uniform splines centred on
// the nodes reproduce constants and linear fields with the node positions as coefficients; at
// a face (node 0, the ghost node -1 beyond it) they need the ghost's function, and the face
// node's value at the face is only 3/4 (2/3). The ghost's function is folded into its two
// neighbours as linear extrapolation does, u_-1 = 2 u_0 - u_1:
//     N_0 += 2 N_-1,   N_1 -= N_-1,   N_-1 = 0     (likewise at the upper face),
// which keeps the partition of unity and linear completeness (the weights 2 and -1 are the
// ones that reproduce 1 and x_-1 = -h from x_0 = 0 and x_1 = h) and makes N_i(face) = 1 for
// the face node and 0 for every other: holding the face node holds the material on the face,
// so rollers and fixed faces act as with hats. N_1 stays non-negative. Ghost nodes never carry
// weight, so the stencil is held inside [0, cells].
#include "talus/core/types.hpp"

#include <algorithm>
#include <cmath>

namespace talus {

template <int Degree> struct BSplineShape {
  static_assert(Degree == 2 || Degree == 3, "quadratic and cubic B-splines");
  static constexpr int kWidth = Degree + 1;
  static constexpr bool kDomainFollowsStretch = false;
  static constexpr const char* kName = Degree == 2 ? "bspline2" : "bspline3";

  /// The first of the kWidth nodes; lp is unused (the spline has no particle domain).
  static Index start(double x, double h, double /*lp*/, Index cells) {
    const Index first = Degree == 2 ? static_cast<Index>(std::floor(x / h - 0.5))
                                    : static_cast<Index>(std::floor(x / h)) - 1;
    return std::clamp<Index>(first, 0, cells - (kWidth - 1));
  }
  static void eval(double x, double h, double /*lp*/, Index cells, Index start, double* N,
                   double* dN) {
    double ghost_low, dghost_low, ghost_high, dghost_high;
    uniform(x / h + 1.0, h, ghost_low, dghost_low);
    uniform(x / h - static_cast<double>(cells + 1), h, ghost_high, dghost_high);
    for (int a = 0; a < kWidth; ++a) {
      const Index i = start + a;
      uniform(x / h - static_cast<double>(i), h, N[a], dN[a]);
      const double fold_low = i == 0 ? 2.0 : i == 1 ? -1.0 : 0.0;
      const double fold_high = i == cells ? 2.0 : i == cells - 1 ? -1.0 : 0.0;
      N[a] += fold_low * ghost_low + fold_high * ghost_high;
      dN[a] += fold_low * dghost_low + fold_high * dghost_high;
    }
  }

  /// The uniform spline at r = (x - x_i) / h and its derivative in x.
  static void uniform(double r, double h, double& N, double& dN) {
    const double ar = std::abs(r);
    const double sign = r >= 0 ? 1.0 : -1.0;
    if constexpr (Degree == 2) {
      if (ar < 0.5) {
        N = 0.75 - r * r;
        dN = -2.0 * r / h;
      } else if (ar < 1.5) {
        const double s = 1.5 - ar;
        N = 0.5 * s * s;
        dN = -sign * s / h;
      } else {
        N = dN = 0.0;
      }
    } else {
      if (ar < 1.0) {
        N = 2.0 / 3.0 - r * r + 0.5 * ar * r * r;
        dN = (-2.0 * r + 1.5 * ar * r) / h;
      } else if (ar < 2.0) {
        const double s = 2.0 - ar;
        N = s * s * s / 6.0;
        dN = -sign * 0.5 * s * s / h;
      } else {
        N = dN = 0.0;
      }
    }
  }
};

using QuadraticBSplineShape = BSplineShape<2>;
using CubicBSplineShape = BSplineShape<3>;

} // namespace talus
