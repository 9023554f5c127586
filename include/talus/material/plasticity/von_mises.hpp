#pragma once
// von Mises (J2) plasticity with linear isotropic hardening, radial return in principal space
// (Wilkins 1964; Simo & Hughes 1998, box 3.2; de Souza Neto, Peric & Owen 2008, box 7.3).
//
//     f = q - sigma_y(kappa),   q = sqrt(3/2) |dev sigma|,   sigma_y = sigma_y0 + H kappa,
//
// with associated flow, so kappa is the equivalent plastic strain. With the trial deviator
// s^tr = 2 mu dev(eps^tr) and q^tr = sqrt(3/2) |s^tr|, the return is
//     Delta kappa = f^tr / (3 mu + H),    s = (1 - 3 mu Delta kappa / q^tr) s^tr,
// and the consistent tangent (box 7.4, written on principal values)
//     D = K 1 1^T + 2 mu (1 - 3 mu Dk / q^tr) (I - 1 1^T / 3)
//         + 6 mu^2 (Dk / q^tr - 1 / (3 mu + H)) n n^T,    n = s^tr / |s^tr|.
// Plane strain needs no special case: eps_33 comes from F_33 = 1 like any other component.
#include "talus/material/plasticity/plastic_model.hpp"

namespace talus {

class VonMises final : public PlasticModel {
public:
  /// Throws InputError unless yield_stress > 0 and hardening_modulus >= 0 (both finite).
  VonMises(const LameParameters& lame, double yield_stress, double hardening_modulus = 0.0);

  const char* name() const override { return "von Mises"; }
  double yield_function(const Vec3& stress, double kappa) const override;
  double yield_stress(double kappa) const { return yield_stress_ + hardening_ * kappa; }

protected:
  PrincipalReturn return_sorted(const Vec3& trial_elastic_strain, double kappa) const override;

private:
  double yield_stress_, hardening_;
};

} // namespace talus
