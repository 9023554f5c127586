#pragma once
// Frictional strength (cohesion c, friction angle phi, dilation angle psi) with optional linear
// softening, shared by Mohr-Coulomb and its Drucker-Prager match.
//
// Softening: c and phi (the angle itself, not sin or tan phi) fall linearly with the
// accumulated plastic shear strain kappa (plastic_model.hpp) from the peak values at kappa = 0
// to the residual values at kappa = kappa_r and stay constant after,
//     c(kappa) = c_p + (c_r - c_p) min(kappa, kappa_r) / kappa_r,   likewise phi(kappa).
// The dilation angle is constant and may not exceed either friction angle (psi <= phi keeps the
// plastic work non-negative). At kappa = kappa_r the slope is taken from the residual side.
#include <optional>

namespace talus {

/// Residual strength reached at kappa = kappa_residual (degrees for the angle).
struct ResidualStrength {
  double cohesion = 0;       ///< c_r, stress units, >= 0
  double friction_angle = 0; ///< phi_r, degrees, [0, 90)
  double kappa = 0;          ///< kappa_r, > 0
};

/// Mohr-Coulomb strength parameters as a case file gives them (angles in degrees).
struct FrictionalStrengthParameters {
  double cohesion = 0;                      ///< c (peak), stress units, >= 0
  double friction_angle = 0;                ///< phi (peak), degrees, [0, 90)
  double dilation_angle = 0;                ///< psi, degrees, 0 <= psi <= min(phi, phi_r)
  std::optional<ResidualStrength> residual; ///< none: perfect plasticity
};

/// c(kappa), phi(kappa) and their slopes; angles in radians.
struct StrengthState {
  double cohesion = 0;
  double cohesion_slope = 0; ///< dc / dkappa
  double friction = 0;       ///< phi, radians
  double friction_slope = 0; ///< dphi / dkappa, radians
};

class FrictionalStrength {
public:
  /// Validates the parameters: throws InputError with the offending key ("cohesion",
  /// "friction_angle", "dilation_angle", "residual.cohesion", "residual.friction_angle",
  /// "residual.kappa") for c < 0, angles outside [0, 90), psi > phi or psi > phi_r, kappa_r <= 0,
  /// no strength at all (c = phi = 0), or a friction angle that softens to 0 from a positive
  /// peak (the apex c cot(phi) would run off to infinity).
  explicit FrictionalStrength(const FrictionalStrengthParameters& parameters);

  StrengthState at(double kappa) const;
  double dilation() const { return dilation_; }   ///< psi, radians
  bool frictional() const { return frictional_; } ///< phi > 0 (there is an apex)

private:
  double c_peak_, c_residual_, phi_peak_, phi_residual_, kappa_residual_, dilation_;
  bool softening_, frictional_;
};

} // namespace talus
