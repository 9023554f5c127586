#pragma once
// Kinematics around the principal return maps: Kirchhoff stress and its consistent tangent
// dtau/dF (row-major 9x9, stress_tangent.hpp) of one material point, from the deformation
// gradients at the start (F_n, converged) and end (F, trial) of the step and the converged
// history.
//
// Finite strain (exponential-map return; Simo 1992; de Souza Neto, Peric & Owen 2008, ch. 14):
//     b_e^tr = f b_e,n f^T,  f = F F_n^{-1}      (b_e,n = I initially)
//            = F A F^T,      A = F_n^{-1} b_e,n F_n^{-T}  (= C_p,n^{-1}, fixed during the step),
//     eps^tr_a = ln(x_a) / 2 for the eigenvalues x_a of b_e^tr, eigenvectors n_a;
//     the principal return gives tau_a (Hencky: Kirchhoff stress = linear law on log strain),
//     tau = sum_a tau_a n_a n_a^T,  b_e = sum_a exp(2 eps^e_a) n_a n_a^T.
// tau is an isotropic function of b_e^tr, so (principal_space.hpp)
//     dtau/dF = [dtau/db_e^tr] : [db_e^tr/dF],   D_ab = (dtau_a/deps^tr_b) / (2 x_b),
//     db_e^tr_ij / dF_kl = delta_ik (F A)_jl + (F A)_il delta_jk.
// The divided differences are taken in strain space and chained with those of the logarithm,
//     theta_ab = [(tau_a - tau_b) / (eps_a - eps_b)] [(eps_a - eps_b) / (x_a - x_b)],
// where tau_a - tau_b = 2 mu (eps^e_a - eps^e_b) (no cancellation of the lambda tr eps term) and
// the second factor is log1p(d) / (2 d x_lo), d = (x_hi - x_lo) / x_lo, as in hencky_response: an
// elastic step reproduces hencky_response to round-off. Coincident strains use the limit
// ((C_aa - C_ab) + (C_bb - C_ba)) / 2.
//
// Small strain (consistent with LinearElastic, hyperelastic.hpp): eps(F) = sym(F) - I,
//     eps^tr = eps^e_n + eps(F) - eps(F_n)    (eps^e_n = 0 initially),
// sigma from the principal return on the eigenvalues of eps^tr, first Piola P = sigma,
// tau = P F^T, and dtau_ij/dF_kl = (dsigma/deps)_im,kl F_jm + sigma_il delta_jk. An elastic step
// reproduces linear_elastic_response.
//
// No heap allocation: everything is fixed-size.
#include "talus/core/types.hpp"
#include "talus/material/plasticity/plastic_model.hpp"
#include "talus/material/stress_tangent.hpp"

#include <cstdint>

namespace talus {

enum class Kinematics : std::uint8_t {
  SmallStrain,  ///< eps = sym(F) - I, tau = sigma F^T (like LinearElastic)
  FiniteStrain, ///< multiplicative, logarithmic elastic strain (like Hencky)
};

/// The per-point state carried from one converged step to the next.
struct PlasticHistory {
  /// Finite strain: the elastic left Cauchy-Green tensor b_e (identity initially).
  /// Small strain: the elastic strain eps_e (zero initially).
  Mat3 elastic = Mat3::Zero();
  /// Accumulated equivalent plastic shear strain (plastic_model.hpp).
  double kappa = 0;

  /// The unstrained state for `kind`.
  static PlasticHistory initial(Kinematics kind);
};

/// Kirchhoff stress and consistent tangent dtau/dF at the trial gradient F_new, from the
/// converged state (F_old, converged). Writes the state belonging to F_new to `updated` (store it
/// once the step converges) and the return type to `type` if given. Throws NumericalError if
/// det F <= 0, b_e^tr is not positive definite or the return fails.
StressTangent elastoplastic_response(const PlasticModel& model, Kinematics kind, const Mat3& F_new,
                                     const Mat3& F_old, const PlasticHistory& converged,
                                     PlasticHistory& updated, ReturnType* type = nullptr);

/// The Kirchhoff stress alone (no 9x9 tangent work), e.g. for the explicit solver.
Mat3 elastoplastic_kirchhoff(const PlasticModel& model, Kinematics kind, const Mat3& F_new,
                             const Mat3& F_old, const PlasticHistory& converged,
                             PlasticHistory& updated, ReturnType* type = nullptr);

} // namespace talus
