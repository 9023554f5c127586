#include "talus/material/plasticity/frictional_strength.hpp"

#include "talus/core/errors.hpp"

#include <cmath>
#include <fmt/format.h>
#include <numbers>

namespace talus {

namespace {

constexpr double kRadian = std::numbers::pi / 180.0;

void require(bool ok, const char* key, const std::string& message) {
  if (!ok)
    throw InputError({"", 0, 0, key}, message);
}

void check_angle(double degrees, const char* key) {
  require(degrees >= 0.0 && degrees < 90.0, key,
          fmt::format("angle must lie in [0, 90) degrees, got {:g}", degrees));
}

} // namespace

FrictionalStrength::FrictionalStrength(const FrictionalStrengthParameters& p) {
  require(p.cohesion >= 0.0 && std::isfinite(p.cohesion), "cohesion",
          fmt::format("cohesion must be non-negative, got {:g}", p.cohesion));
  check_angle(p.friction_angle, "friction_angle");
  check_angle(p.dilation_angle, "dilation_angle");
  require(p.dilation_angle <= p.friction_angle, "dilation_angle",
          fmt::format("dilation angle {:g} exceeds the friction angle {:g}", p.dilation_angle,
                      p.friction_angle));
  require(p.cohesion > 0.0 || p.friction_angle > 0.0, "cohesion",
          "cohesion and friction angle are both zero: the material has no strength");
  const ResidualStrength r = p.residual.value_or(ResidualStrength{p.cohesion, p.friction_angle, 1});
  if (p.residual) {
    require(r.cohesion >= 0.0 && std::isfinite(r.cohesion), "residual.cohesion",
            fmt::format("residual cohesion must be non-negative, got {:g}", r.cohesion));
    check_angle(r.friction_angle, "residual.friction_angle");
    require(r.kappa > 0.0 && std::isfinite(r.kappa), "residual.kappa",
            fmt::format("softening strain kappa_r must be positive, got {:g}", r.kappa));
    require(p.dilation_angle <= r.friction_angle, "dilation_angle",
            fmt::format("dilation angle {:g} exceeds the residual friction angle {:g}",
                        p.dilation_angle, r.friction_angle));
    require((r.friction_angle > 0.0) == (p.friction_angle > 0.0), "residual.friction_angle",
            "the friction angle must be zero at both peak and residual, or positive at both");
    require(r.cohesion > 0.0 || r.friction_angle > 0.0, "residual.cohesion",
            "residual cohesion and friction angle are both zero: no residual strength");
  }
  c_peak_ = p.cohesion;
  c_residual_ = r.cohesion;
  phi_peak_ = p.friction_angle * kRadian;
  phi_residual_ = r.friction_angle * kRadian;
  kappa_residual_ = r.kappa;
  dilation_ = p.dilation_angle * kRadian;
  softening_ = p.residual.has_value();
  frictional_ = p.friction_angle > 0.0;
}

StrengthState FrictionalStrength::at(double kappa) const {
  if (!softening_ || kappa >= kappa_residual_) {
    return {c_residual_, 0.0, phi_residual_, 0.0};
  }
  const double t = kappa / kappa_residual_;
  const double dc = (c_residual_ - c_peak_) / kappa_residual_;
  const double dphi = (phi_residual_ - phi_peak_) / kappa_residual_;
  return {c_peak_ + t * (c_residual_ - c_peak_), dc, phi_peak_ + t * (phi_residual_ - phi_peak_),
          dphi};
}

} // namespace talus
