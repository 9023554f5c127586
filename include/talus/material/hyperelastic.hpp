#pragma once
// Pointwise elastic laws in Kirchhoff form with their consistent tangents, the material side of
// the implicit (Newton) solver. The Material classes in material.hpp evaluate the same laws for
// particle batches (sigma = tau / J); the *_kirchhoff functions are the stress-only versions
// (no tangent work) used there.
//
// All tangents use the row-major flattening of principal_space.hpp:
// dtau_dF(3*i + j, 3*k + l) = d tau_ij / d F_kl.
#include "talus/core/types.hpp"
#include "talus/material/material.hpp"
#include "talus/material/principal_space.hpp"
#include "talus/material/stress_tangent.hpp"

namespace talus {

/// Small-strain linear elasticity as a hyperelastic law: stored energy
/// W = lambda/2 (tr eps)^2 + mu eps:eps with eps = sym(F) - I, first Piola P = dW/dF =
/// lambda tr(eps) I + 2 mu eps, and tau = P F^T. For small displacements tau = sigma is the
/// textbook linear law; deriving it from W keeps the implicit tangent symmetric. Not objective
/// under finite rotation (use neo_hookean or hencky there). Defined for any F.
Mat3 linear_elastic_kirchhoff(const Mat3& F, const LameParameters& lame);
/// tau as above and its derivative dtau/dF.
StressTangent linear_elastic_response(const Mat3& F, const LameParameters& lame);
/// Compressible neo-Hookean: tau = mu (b - I) + lambda ln(J) I, b = F F^T, J = det F.
/// Throws NumericalError if J <= 0.
Mat3 neo_hookean_kirchhoff(const Mat3& F, const LameParameters& lame);
/// tau as above and dtau_dF = mu d(b)/dF + lambda I (x) F^{-T}.
StressTangent neo_hookean_response(const Mat3& F, const LameParameters& lame);

/// Hencky (logarithmic-strain) hyperelasticity: tau = lambda tr(e) I + 2 mu e with the
/// Eulerian logarithmic strain e = 1/2 ln(b), b = F F^T; stored energy
/// psi = mu e:e + lambda/2 (tr e)^2. Evaluated in the principal frame of b.
/// Throws NumericalError if det F <= 0 (b alone cannot see an inverted F).
Mat3 hencky_kirchhoff(const Mat3& F, const LameParameters& lame);
/// tau as above and dtau_dF = (d tau / d b) : (d b / d F), d tau / d b from the isotropic tensor
/// function derivative (principal_space.hpp) with a cancellation-free closed form for the
/// divided differences of ln, exact for repeated principal stretches.
StressTangent hencky_response(const Mat3& F, const LameParameters& lame);

} // namespace talus
