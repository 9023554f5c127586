#pragma once
// A scalar expression of the initial position, e.g. "0.01 * sin(pi / 50 * x)", for fields a
// case sets per point (initial velocity). Parsed once by muparser, evaluated per point.
#include <memory>
#include <string>

namespace talus {

class PositionExpression {
public:
  /// Throws std::invalid_argument with the parser's message if `text` is not a valid
  /// expression in the variables x and y (constants: pi, e; functions: sin, cos, exp, ...).
  explicit PositionExpression(const std::string& text);
  ~PositionExpression();
  PositionExpression(PositionExpression&&) noexcept;
  PositionExpression& operator=(PositionExpression&&) noexcept;

  double operator()(double x, double y) const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

} // namespace talus
