#pragma once
// The common interface of the elasto-plastic soil models: a return map in principal space.
//
// Every model here is isotropic, with linear isotropic elasticity in principal strains,
//     sigma_a = lambda (eps_1 + eps_2 + eps_3) + 2 mu eps_a,
// so the elastic predictor and the plastic corrector both act on three principal values and
// share the eigenvectors of the trial strain (de Souza Neto, Peric & Owen 2008, ch. 8). The
// same return serves small strain (eps = engineering strain, sigma = Cauchy stress) and finite
// strain (eps = logarithmic elastic strain, sigma = Kirchhoff stress; Simo 1992), see
// elastoplastic_response.hpp.
//
// Sign convention: tension positive. Inside a model the principal values are sorted
// descending, sigma_1 >= sigma_2 >= sigma_3, so sigma_3 is the most compressive stress.
//
// Internal variable kappa: the accumulated equivalent plastic shear strain,
//     kappa_{n+1} = kappa_n + sqrt(2/3) |dev(Delta eps^p)|,
// with Delta eps^p the plastic strain increment of the step (principal, so |.| is the Euclidean
// norm of three values). For von Mises it is the classical equivalent plastic strain; for a
// return to one plane of potential g it is Delta gamma sqrt(2/3) |dev(dg/dsigma)|; at an apex
// all of the trial deviatoric strain is plastic, Delta kappa = sqrt(2/3) |dev(eps^tr)|.
#include "talus/core/types.hpp"
#include "talus/material/material.hpp"

#include <array>
#include <cstdint>

namespace talus {

/// Which part of the yield surface the stress returned to.
enum class ReturnType : std::uint8_t {
  Elastic,         ///< trial state admissible, no plastic flow
  Surface,         ///< smooth part: one plane (Tresca, Mohr-Coulomb), cone (DP), cylinder (VM)
  CompressionEdge, ///< edge sigma_1 = sigma_2 > sigma_3 (triaxial compression meridian)
  ExtensionEdge,   ///< edge sigma_1 > sigma_2 = sigma_3 (triaxial extension meridian)
  Apex,            ///< hydrostatic tip of a frictional surface, sigma_a = c cot(phi)
};

/// Lower-case name of a return type, e.g. "compression edge".
const char* to_string(ReturnType type);

/// Result of a principal return map. All vectors are in the order of the trial strain passed in.
struct PrincipalReturn {
  Vec3 stress = Vec3::Zero();         ///< principal stress
  Mat3 tangent = Mat3::Zero();        ///< algorithmic d stress_a / d trial_strain_b
  Vec3 elastic_strain = Vec3::Zero(); ///< updated principal elastic strain
  double kappa = 0;                   ///< updated accumulated plastic shear strain
  ReturnType type = ReturnType::Elastic;
};

/// Lame parameters from Young's modulus and Poisson's ratio; throws InputError (key
/// "youngs_modulus" or "poisson_ratio") unless E > 0 and -1 < nu < 0.5.
LameParameters checked_lame_parameters(double youngs_modulus, double poisson_ratio);

/// An elasto-plastic model as a principal-space return map.
class PlasticModel {
public:
  /// Throws InputError unless mu > 0 and the bulk modulus lambda + 2 mu / 3 > 0 (both finite).
  explicit PlasticModel(const LameParameters& lame);
  virtual ~PlasticModel() = default;

  /// Name for messages, e.g. "Mohr-Coulomb".
  virtual const char* name() const = 0;
  const LameParameters& lame() const { return lame_; }

  /// Elastic predictor and plastic corrector for the principal trial elastic strain (any order)
  /// and the converged kappa of the step's start. Throws NumericalError if the local iteration
  /// fails.
  PrincipalReturn return_map(const Vec3& trial_elastic_strain, double kappa) const;

  /// Yield function f(sigma, kappa), principal stress in any order; f <= 0 is admissible. It is
  /// scaled like a stress (e.g. Mohr-Coulomb: sigma_1 - sigma_3 + ... - 2 c cos(phi)).
  virtual double yield_function(const Vec3& stress, double kappa) const = 0;

  /// sigma = lambda tr(eps) 1 + 2 mu eps in principal values.
  Vec3 elastic_stress(const Vec3& strain) const;
  /// The principal elastic stiffness lambda 1 1^T + 2 mu I.
  Mat3 elastic_stiffness() const;

protected:
  /// The return map proper, on a trial strain sorted descending (eps_1 >= eps_2 >= eps_3, hence
  /// sigma_1 >= sigma_2 >= sigma_3 since mu > 0). Results in the same sorted order.
  virtual PrincipalReturn return_sorted(const Vec3& trial_elastic_strain, double kappa) const = 0;

private:
  LameParameters lame_;
};

/// Principal values sorted descending, and back: sorted(i) = v(order[i]).
struct DescendingOrder {
  std::array<int, 3> order{0, 1, 2};
  explicit DescendingOrder(const Vec3& v);
  Vec3 sort(const Vec3& v) const;
  Vec3 unsort(const Vec3& sorted) const;
  Mat3 unsort(const Mat3& sorted) const;
};

/// The deviator of three principal values: v - mean(v).
inline Vec3 deviator(const Vec3& v) {
  return v - Vec3::Constant(v.sum() / 3.0);
}

/// The deviatoric projector in principal space, I - 1 1^T / 3.
inline Mat3 deviatoric_projector() {
  return Mat3::Identity() - Mat3::Constant(1.0 / 3.0);
}

} // namespace talus
