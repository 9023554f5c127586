#pragma once
// A scalar expression of the initial position, e.g. "0.01 * sin(pi / 50 * x)", for fields a
// case sets per point (initial velocity). Parsed once by muparser, evaluated per point.
#include "talus/core/types.hpp"

#include <memory>
#include <string>

namespace talus {

class PositionExpression {
public:
  /// Throws std::invalid_argument with the parser's message if `text` is not a valid
  /// expression in the variables x and y, and z in 3D (constants: pi, e; functions: sin, cos,
  /// exp, ...).
  PositionExpression(const std::string& text, int dimension);
  ~PositionExpression();
  PositionExpression(PositionExpression&&) noexcept;
  PositionExpression& operator=(PositionExpression&&) noexcept;

  /// The value at x (z unused in 2D).
  double operator()(const Vec3& x) const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

} // namespace talus
