#pragma once
// One-dimensional MPM basis functions; the solver forms tensor products. Each kernel says how
// many nodes per direction can be non-zero (its stencil width) and fills values and derivatives
// for the nodes start, start + 1, ..., start + width - 1.
//
//  * LinearShape: standard MPM hat functions, N(r) = 1 - |r|/h.
//  * GimpShape: uGIMP (Bardenhagen & Kober 2004), the hat function averaged over a particle
//    domain of half-width lp <= h/2 that keeps its initial size.
#include "talus/core/types.hpp"
#include "talus/io/case_spec.hpp"

#include <cmath>
#include <memory>
#include <stdexcept>

namespace talus {

struct LinearShape {
  static constexpr int kWidth = 2;
  static constexpr const char* kName = "linear";
  /// x: particle coordinate relative to the grid origin; lp is unused.
  static Index start(double x, double h, double /*lp*/) {
    return static_cast<Index>(std::floor(x / h));
  }
  static void eval(double x, double h, double /*lp*/, Index start, double* N, double* dN) {
    // Half-open cells [x_start, x_start + h): the gradients of the two hats always sum to zero,
    // also for a particle sitting exactly on a node.
    const double xi = x / h - static_cast<double>(start);
    N[0] = 1.0 - xi;
    N[1] = xi;
    dN[0] = -1.0 / h;
    dN[1] = 1.0 / h;
  }
};

struct GimpShape {
  static constexpr int kWidth = 3;
  static constexpr const char* kName = "gimp";
  static Index start(double x, double h, double lp) {
    return static_cast<Index>(std::floor((x - lp) / h));
  }
  /// Value and derivative of the uGIMP function for distance r = x_p - x_i.
  static void value(double r, double h, double lp, double& N, double& dN) {
    const double ar = std::abs(r);
    const double sign = r >= 0 ? 1.0 : -1.0;
    if (ar < lp) {
      N = 1.0 - (r * r + lp * lp) / (2.0 * h * lp);
      dN = -r / (h * lp);
    } else if (ar < h - lp) {
      N = 1.0 - ar / h;
      dN = -sign / h;
    } else if (ar < h + lp) {
      const double s = h + lp - ar;
      N = s * s / (4.0 * h * lp);
      dN = -sign * s / (2.0 * h * lp);
    } else {
      N = 0.0;
      dN = 0.0;
    }
  }
  static void eval(double x, double h, double lp, Index start, double* N, double* dN) {
    for (int a = 0; a < kWidth; ++a)
      value(x - h * static_cast<double>(start + a), h, lp, N[a], dN[a]);
  }
};

/// Instantiates Solver<Shape> for the case's shape function: the one place where the run-time
/// choice becomes a compile-time parameter of the hot loops.
template <class Base, template <class> class Solver, class... Args>
std::unique_ptr<Base> make_for_shape(ShapeFunction shape, Args&... args) {
  switch (shape) {
  case ShapeFunction::Linear:
    return std::make_unique<Solver<LinearShape>>(args...);
  case ShapeFunction::Gimp:
    return std::make_unique<Solver<GimpShape>>(args...);
  }
  throw std::logic_error("unknown shape function");
}

} // namespace talus
