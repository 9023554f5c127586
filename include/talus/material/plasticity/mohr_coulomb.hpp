#pragma once
// Mohr-Coulomb plasticity with a non-associated (dilation angle psi <= phi) flow rule and
// optional softening of c and phi, returned exactly in principal stress space (no smoothing).
//
// With sigma_1 >= sigma_2 >= sigma_3 (tension positive) the yield function and the plastic
// potential are the planes
//     f = (1 + sin phi) sigma_1 - (1 - sin phi) sigma_3 - 2 c cos phi,
//     g = (1 + sin psi) sigma_1 - (1 - sin psi) sigma_3,
// i.e. (sigma_1 - sigma_3)/2 = c cos phi - (sigma_1 + sigma_3)/2 sin phi. In compression this is
// |sigma_3| = K_p |sigma_1| + 2 c sqrt(K_p), K_p = (1 + sin phi) / (1 - sin phi). The six planes
// of all orderings form a hexagonal pyramid with edges on the triaxial compression
// (sigma_1 = sigma_2) and extension (sigma_2 = sigma_3) meridians and its apex at
// sigma_a = c cot phi.
//
// Return map (de Souza Neto, Peric & Owen 2008, sec. 8.2 and box 8.5, their SUMC routine;
// Clausen, Damkilde & Andersen 2006, 2007 derive the same regions geometrically):
//  1. elastic if f(sigma^tr, kappa_n) <= 0;
//  2. main plane: sigma = sigma^tr - dg D b, b = dg/dsigma, with f(sigma, kappa) = 0; valid if
//     sigma keeps the order sigma_1 >= sigma_2 >= sigma_3;
//  3. otherwise an edge: the second plane is sigma_1 vs sigma_2 (extension edge) if
//     (1 - sin psi) s_1 - 2 s_2 + (1 + sin psi) s_3 >= 0 for the trial stress s, else sigma_2 vs
//     sigma_3 (compression edge). The sign tells which order the one-plane return breaks first:
//     it lowers sigma_1 - sigma_2 by 2 mu dg (1 + sin psi) and sigma_2 - sigma_3 by
//     2 mu dg (1 - sin psi). Two multipliers, both planes f = 0; valid unless the stress passes
//     beyond the apex (the edge's free pair loses its order);
//  4. otherwise the apex: all deviatoric trial strain is plastic, so
//     kappa = kappa_n + sqrt(2/3) |dev eps^tr| is known before the stress and
//     sigma_a = c(kappa) cot phi(kappa). (With psi = 0 no flow direction has a volumetric part;
//     the apex is then the limit of the edge returns, which no finite multipliers reach.)
// With softening, kappa = kappa_n + sqrt(2/3) |dev(sum_i dg_i b_i)| makes steps 2 and 3 a
// small nonlinear system, solved by Newton from the perfectly plastic (frozen strength)
// solution; without softening that start is already the exact, closed-form answer.
//
// Consistent tangent: differentiate the converged local system r(dg, sigma^tr) = 0 (implicit
// function theorem). With A the rows df_i/dsigma, M = [D b_1, D b_2] and J = dr/d(dg) (which
// carries the softening terms, making the tangent nonsymmetric),
//     d sigma / d eps^tr = (I + M J^{-1} A) D;
// at the apex d sigma_a / d eps^tr_b = dp/dkappa sqrt(2/3) (dev eps^tr / |dev eps^tr|)_b (zero for
// a purely hydrostatic trial strain, where that direction is undefined).
#include "talus/material/plasticity/frictional_strength.hpp"
#include "talus/material/plasticity/plastic_model.hpp"

namespace talus {

class MohrCoulomb : public PlasticModel {
public:
  /// Throws InputError for bad elastic or strength parameters (frictional_strength.hpp).
  MohrCoulomb(const LameParameters& lame, const FrictionalStrengthParameters& strength);

  const char* name() const override { return "Mohr-Coulomb"; }
  double yield_function(const Vec3& stress, double kappa) const override;
  const FrictionalStrength& strength() const { return strength_; }

protected:
  PrincipalReturn return_sorted(const Vec3& trial_elastic_strain, double kappa) const override;

private:
  PrincipalReturn apex_return(const Vec3& trial_elastic_strain, double kappa) const;

  FrictionalStrength strength_;
};

} // namespace talus
