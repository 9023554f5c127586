#pragma once
// Drucker-Prager plasticity matched to Mohr-Coulomb in plane strain, with a non-associated flow
// rule and the softening of c and phi carried through the match.
//
//     f = sqrt(J2) + alpha I1 - k,   g = sqrt(J2) + alpha_g I1,
// J2 = |dev sigma|^2 / 2, I1 = tr sigma (tension positive); the cone's apex is at
// I1 = k / alpha, i.e. sigma_a = k / (3 alpha).
//
// Plane-strain match. In plane strain at failure the out-of-plane plastic strain rate vanishes,
// dg/dsigma_zz = 0. Writing t = (sigma_1 - sigma_3)/2 and m = (sigma_1 + sigma_3)/2 for the
// in-plane principal stresses, that fixes sigma_zz and gives sqrt(J2) = t / sqrt(1 - 3 alpha_g^2),
// so the cone becomes the Mohr-Coulomb line t + m sin(phi) = c cos(phi) exactly when, with
// S = sqrt(9 + 3 sin^2 psi),
//     alpha_g = sin(psi) / S                          (= tan psi / sqrt(9 + 12 tan^2 psi)),
//     alpha   = sin(phi) S / (3 (3 + sin(phi) sin(psi))),
//     k       = c cos(phi) S / (3 + sin(phi) sin(psi)).
// alpha_g makes the plane-strain dilatancy ratio of the cone's flow, eps_v / (eps_1 - eps_3),
// equal to Mohr-Coulomb's sin(psi). For associated flow (psi = phi) this is the classical
//     alpha = tan(phi) / sqrt(9 + 12 tan^2 phi),   k = 3 c / sqrt(9 + 12 tan^2 phi)
// (de Souza Neto, Peric & Owen 2008, sec. 6.4.3, their eta = 3 alpha, xi c = k), and for any psi
// the apex k / (3 alpha) = c cot(phi) coincides with Mohr-Coulomb's.
//
// Return map (de Souza Neto et al., box 8.9, on principal values): with e = dev eps^tr,
// rho = |e|, sqrt(J2^tr) = sqrt(2) mu rho and I1^tr = 3 K tr(eps^tr),
//  cone:  sqrt(J2) = sqrt(J2^tr) - mu dg, I1 = I1^tr - 9 K alpha_g dg, kappa = kappa_n + dg/sqrt(3)
//         (the flow's deviator has norm 1/sqrt(2)), r(dg) = sqrt(J2) + alpha I1 - k = 0 by
//         Newton; valid while sqrt(J2) >= 0;
//  apex:  kappa = kappa_n + sqrt(2/3) rho, sigma_a = c(kappa) cot phi(kappa).
// Cone tangent, with n = e / rho and dr/deps = sqrt(2) mu n + 3 K alpha 1, ddg = -dr/deps / r',
//     D = K 1 1^T + 2 mu P - sqrt(2) mu dg (P - n n^T) / rho - (3 K alpha_g 1 + sqrt(2) mu n) ddg^T
// where P = I - 1 1^T / 3; r' = dr/ddg carries the softening (nonsymmetric tangent).
#include "talus/material/plasticity/frictional_strength.hpp"
#include "talus/material/plasticity/plastic_model.hpp"

namespace talus {

/// Drucker-Prager coefficients of the plane-strain match (angles in radians) and their
/// derivatives with respect to c and phi (for softening).
struct DruckerPragerMatch {
  double alpha = 0, k = 0, alpha_flow = 0;
  double dalpha_dphi = 0, dk_dphi = 0, dk_dc = 0;
};
DruckerPragerMatch plane_strain_match(double cohesion, double friction, double dilation);

class DruckerPrager final : public PlasticModel {
public:
  /// The cone matching Mohr-Coulomb with these strength parameters in plane strain. Throws
  /// InputError for bad elastic or strength parameters (frictional_strength.hpp).
  DruckerPrager(const LameParameters& lame, const FrictionalStrengthParameters& strength);

  const char* name() const override { return "Drucker-Prager"; }
  double yield_function(const Vec3& stress, double kappa) const override;
  const FrictionalStrength& strength() const { return strength_; }
  DruckerPragerMatch coefficients(double kappa) const;

protected:
  PrincipalReturn return_sorted(const Vec3& trial_elastic_strain, double kappa) const override;

private:
  FrictionalStrength strength_;
};

} // namespace talus
