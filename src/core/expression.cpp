#include "talus/core/expression.hpp"

#include <muParser.h>
#include <numbers>
#include <stdexcept>

namespace talus {

struct PositionExpression::Impl {
  mu::Parser parser;
  double x = 0, y = 0, z = 0;
};

PositionExpression::PositionExpression(const std::string& text, int dimension)
    : impl_(std::make_unique<Impl>()) {
  try {
    impl_->parser.DefineVar("x", &impl_->x);
    impl_->parser.DefineVar("y", &impl_->y);
    if (dimension == 3)
      impl_->parser.DefineVar("z", &impl_->z);
    impl_->parser.DefineConst("pi", std::numbers::pi);
    impl_->parser.DefineConst("e", std::numbers::e);
    impl_->parser.SetExpr(text);
    impl_->parser.Eval(); // parse now so errors surface while reading the case
  } catch (const mu::Parser::exception_type& e) {
    throw std::invalid_argument("invalid expression '" + text + "': " + e.GetMsg());
  }
}

PositionExpression::~PositionExpression() = default;
PositionExpression::PositionExpression(PositionExpression&&) noexcept = default;
PositionExpression& PositionExpression::operator=(PositionExpression&&) noexcept = default;

double PositionExpression::operator()(const Vec3& x) const {
  impl_->x = x.x();
  impl_->y = x.y();
  impl_->z = x.z();
  return impl_->parser.Eval();
}

} // namespace talus
