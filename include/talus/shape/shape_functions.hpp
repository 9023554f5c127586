#pragma once
// One-dimensional MPM basis functions; the solver forms tensor products. Each kernel says how
// many nodes per direction can be non-zero (its stencil width, kWidth), whether the particle
// domain it averages over follows the point's stretch (kDomainFollowsStretch,
// shape/deformed_domain.hpp), and fills values and derivatives for the nodes start, start + 1,
// ..., start + width - 1. Every kernel takes the particle coordinate x relative to the grid
// origin, the cell size h, the domain half-width lp and the number of cells on the axis (the
// B-splines are modified at the grid's faces).
//
//  * LinearShape: standard MPM hat functions, N(r) = 1 - |r|/h.
//  * GimpShape, CpGimpShape (shape/gimp.hpp): the hat averaged over the particle domain, kept
//    at its initial size (uGIMP) or stretched with the point (cpGIMP).
//  * BSplineShape<2>, BSplineShape<3> (shape/bspline.hpp): quadratic and cubic B-splines,
//    boundary-modified at the grid's faces.
//  * CpdiShape (shape/cpdi.hpp): CPDI over the deformed voxel, not a tensor product; it fills
//    a point's weights on all its stencil's nodes at once.
#include "talus/core/types.hpp"
#include "talus/shape/bspline.hpp"
#include "talus/shape/cpdi.hpp"
#include "talus/shape/gimp.hpp"
#include "talus/spec/case_spec.hpp"

#include <cmath>
#include <memory>
#include <stdexcept>

namespace talus {

struct LinearShape {
  static constexpr int kWidth = 2;
  static constexpr bool kDomainFollowsStretch = false;
  static constexpr const char* kName = "linear";
  /// x: particle coordinate relative to the grid origin; lp is unused.
  static Index start(double x, double h, double /*lp*/, Index /*cells*/) {
    return static_cast<Index>(std::floor(x / h));
  }
  static void eval(double x, double h, double /*lp*/, Index /*cells*/, Index start, double* N,
                   double* dN) {
    // Half-open cells [x_start, x_start + h): the gradients of the two hats always sum to zero,
    // also for a particle sitting exactly on a node.
    const double xi = x / h - static_cast<double>(start);
    N[0] = 1.0 - xi;
    N[1] = xi;
    dN[0] = -1.0 / h;
    dN[1] = 1.0 / h;
  }
};

/// Whether a shape's weights are tensor products of 1D kernels (all but CPDI).
template <class Shape> constexpr bool tensor_product() {
  if constexpr (requires { Shape::kTensorProduct; })
    return Shape::kTensorProduct;
  else
    return true;
}

/// Nodes per direction of a shape's stencil.
constexpr int stencil_width(ShapeFunction shape) {
  switch (shape) {
  case ShapeFunction::Linear:
    return LinearShape::kWidth;
  case ShapeFunction::Gimp:
    return GimpShape::kWidth;
  case ShapeFunction::CpGimp:
    return CpGimpShape::kWidth;
  case ShapeFunction::BSpline2:
    return QuadraticBSplineShape::kWidth;
  case ShapeFunction::BSpline3:
    return CubicBSplineShape::kWidth;
  case ShapeFunction::Cpdi:
    return CpdiShape::kWidth;
  }
  return 0;
}

/// Instantiates Solver<Shape> for the case's shape function: the one place where the run-time
/// choice becomes a compile-time parameter of the hot loops.
template <class Base, template <class> class Solver, class... Args>
std::unique_ptr<Base> make_for_shape(ShapeFunction shape, Args&... args) {
  switch (shape) {
  case ShapeFunction::Linear:
    return std::make_unique<Solver<LinearShape>>(args...);
  case ShapeFunction::Gimp:
    return std::make_unique<Solver<GimpShape>>(args...);
  case ShapeFunction::CpGimp:
    return std::make_unique<Solver<CpGimpShape>>(args...);
  case ShapeFunction::BSpline2:
    return std::make_unique<Solver<QuadraticBSplineShape>>(args...);
  case ShapeFunction::BSpline3:
    return std::make_unique<Solver<CubicBSplineShape>>(args...);
  case ShapeFunction::Cpdi:
    return std::make_unique<Solver<CpdiShape>>(args...);
  }
  throw std::logic_error("unknown shape function");
}

} // namespace talus
