#pragma once
// Trial states shared by the plasticity tests: for every model and every return type a principal
// trial elastic strain (and converged kappa) that lands in that return, well inside its region
// (the finite-difference steps below never cross into a neighbouring region). Each test asserts
// the return type first, so a moved region boundary fails loudly instead of silently testing
// another branch.
//
// Material: E = 20 MPa, nu = 0.3 (mu = 7.7 MPa), c = 20 kPa: yield strains of order 1e-3, trial
// strains of order 1e-2.
#include "talus/material/plasticity/drucker_prager.hpp"
#include "talus/material/plasticity/mohr_coulomb.hpp"
#include "talus/material/plasticity/plastic_model.hpp"
#include "talus/material/plasticity/tresca.hpp"
#include "talus/material/plasticity/von_mises.hpp"

#include <memory>
#include <string>
#include <vector>

namespace talus::test {

inline const LameParameters kSoilLame = LameParameters::from_young_poisson(2.0e7, 0.3);

/// Principal strain with volumetric part ev and deviatoric length rho along a direction between
/// triaxial extension (t = 0: 2, -1, -1) and compression (t = 1: 1, 1, -2), sorted descending;
/// t = 0.5 is pure shear (1, 0, -1).
inline Vec3 trial_strain(double ev, double rho, double t) {
  const Vec3 d = (1.0 - t) * Vec3(2.0, -1.0, -1.0) + t * Vec3(1.0, 1.0, -2.0);
  return Vec3::Constant(ev / 3.0) + rho * d.normalized();
}

/// The same values in another order (the return map must not care).
inline Vec3 shuffled(const Vec3& v) {
  return {v(2), v(0), v(1)};
}

struct ReturnCase {
  std::string name;
  std::shared_ptr<const PlasticModel> model;
  Vec3 trial;   ///< principal trial elastic strain, any order
  double kappa; ///< converged kappa at the step's start
  ReturnType expected;
};

inline FrictionalStrengthParameters mc(double c, double phi, double psi) {
  return {c, phi, psi, {}};
}

/// Softening from (c, phi) = (20 kPa, 35 deg) to (5 kPa, 25 deg) at kappa_r = 0.02, psi = 5 deg.
inline FrictionalStrengthParameters softening() {
  return {2.0e4, 35.0, 5.0, ResidualStrength{5.0e3, 25.0, 0.02}};
}

inline std::vector<ReturnCase> return_cases() {
  using RT = ReturnType;
  std::vector<ReturnCase> cases;
  auto add = [&](const std::string& model_name, std::shared_ptr<const PlasticModel> m,
                 const std::string& point, const Vec3& trial, double kappa, RT type) {
    cases.push_back({model_name + ": " + point, std::move(m), trial, kappa, type});
  };

  // von Mises, perfect and hardening (sigma_y = 40 kPa)
  for (const double H : {0.0, 2.0e6}) {
    const auto m = std::make_shared<VonMises>(kSoilLame, 4.0e4, H);
    const std::string n = H == 0.0 ? "von Mises perfect" : "von Mises hardening";
    add(n, m, "elastic", trial_strain(-2e-3, 1e-3, 0.3), 0.0, RT::Elastic);
    add(n, m, "surface, general", shuffled(trial_strain(-2e-3, 1e-2, 0.3)), 0.01, RT::Surface);
    add(n, m, "surface, repeated (compression)", trial_strain(-2e-3, 1e-2, 1.0), 0.0, RT::Surface);
  }

  // Tresca, c = 20 kPa
  {
    const auto m = std::make_shared<Tresca>(kSoilLame, 2.0e4);
    const std::string n = "Tresca";
    add(n, m, "elastic", trial_strain(-3e-3, 1e-3, 0.5), 0.0, RT::Elastic);
    add(n, m, "plane", shuffled(trial_strain(-3e-3, 1e-2, 0.5)), 0.0, RT::Surface);
    add(n, m, "compression edge", trial_strain(-3e-3, 1e-2, 0.9), 0.0, RT::CompressionEdge);
    add(n, m, "compression edge, repeated", shuffled(trial_strain(-3e-3, 1e-2, 1.0)), 0.0,
        RT::CompressionEdge);
    add(n, m, "extension edge", trial_strain(-3e-3, 1e-2, 0.1), 0.0, RT::ExtensionEdge);
    add(n, m, "extension edge, repeated", trial_strain(-3e-3, 1e-2, 0.0), 0.0, RT::ExtensionEdge);
  }

  // Mohr-Coulomb, c = 20 kPa, phi = 30 deg, associated and non-associated
  for (const double psi : {30.0, 10.0, 0.0}) {
    const auto m = std::make_shared<MohrCoulomb>(kSoilLame, mc(2.0e4, 30.0, psi));
    const std::string n = "Mohr-Coulomb psi=" + std::to_string(static_cast<int>(psi));
    add(n, m, "elastic", trial_strain(-3e-3, 3e-3, 0.5), 0.0, RT::Elastic);
    add(n, m, "plane", shuffled(trial_strain(-3e-3, 6e-3, 0.5)), 0.0, RT::Surface);
    add(n, m, "compression edge", trial_strain(0.0, 1e-2, 0.9), 0.0, RT::CompressionEdge);
    add(n, m, "compression edge, repeated", shuffled(trial_strain(0.0, 1e-2, 1.0)), 0.0,
        RT::CompressionEdge);
    add(n, m, "extension edge", trial_strain(0.0, 1e-2, 0.1), 0.0, RT::ExtensionEdge);
    add(n, m, "extension edge, repeated", trial_strain(0.0, 1e-2, 0.0), 0.0, RT::ExtensionEdge);
    add(n, m, "apex", shuffled(trial_strain(1.2e-2, 3e-3, 0.3)), 0.0, RT::Apex);
    add(n, m, "apex, hydrostatic (triple)", trial_strain(6e-3, 0.0, 0.0), 0.0, RT::Apex);
  }

  // Mohr-Coulomb with softening: on the softening branch, crossing kappa_r in the step, residual
  {
    const auto m = std::make_shared<MohrCoulomb>(kSoilLame, softening());
    const std::string n = "Mohr-Coulomb softening";
    for (const double kappa : {0.005, 0.03}) {
      const std::string k = kappa < 0.02 ? " (softening branch)" : " (residual)";
      add(n, m, "plane" + k, shuffled(trial_strain(-3e-3, 8e-3, 0.5)), kappa, RT::Surface);
      add(n, m, "compression edge" + k, trial_strain(0.0, 1e-2, 0.9), kappa, RT::CompressionEdge);
      add(n, m, "compression edge, repeated" + k, trial_strain(0.0, 1e-2, 1.0), kappa,
          RT::CompressionEdge);
      add(n, m, "extension edge" + k, trial_strain(0.0, 1e-2, 0.1), kappa, RT::ExtensionEdge);
      add(n, m, "apex" + k, shuffled(trial_strain(1.2e-2, 3e-3, 0.3)), kappa, RT::Apex);
    }
    add(n, m, "plane crossing kappa_r", trial_strain(-3e-3, 3e-2, 0.5), 0.012, RT::Surface);
    add(n, m, "compression edge crossing kappa_r", trial_strain(0.0, 3e-2, 0.9), 0.012,
        RT::CompressionEdge);
    add(n, m, "apex crossing kappa_r", trial_strain(1.2e-2, 1.2e-2, 0.3), 0.012, RT::Apex);
  }

  // Drucker-Prager, plane-strain match of the same Mohr-Coulomb parameters
  for (const double psi : {30.0, 10.0, 0.0}) {
    const auto m = std::make_shared<DruckerPrager>(kSoilLame, mc(2.0e4, 30.0, psi));
    const std::string n = "Drucker-Prager psi=" + std::to_string(static_cast<int>(psi));
    add(n, m, "elastic", trial_strain(-3e-3, 2e-3, 0.5), 0.0, RT::Elastic);
    add(n, m, "cone", shuffled(trial_strain(-3e-3, 1e-2, 0.3)), 0.0, RT::Surface);
    add(n, m, "cone, repeated", trial_strain(-3e-3, 1e-2, 1.0), 0.0, RT::Surface);
    add(n, m, "apex", shuffled(trial_strain(1.2e-2, 2e-3, 0.3)), 0.0, RT::Apex);
    add(n, m, "apex, hydrostatic (triple)", trial_strain(6e-3, 0.0, 0.0), 0.0, RT::Apex);
  }
  {
    const auto m = std::make_shared<DruckerPrager>(kSoilLame, softening());
    const std::string n = "Drucker-Prager softening";
    for (const double kappa : {0.005, 0.03}) {
      const std::string k = kappa < 0.02 ? " (softening branch)" : " (residual)";
      add(n, m, "cone" + k, shuffled(trial_strain(-3e-3, 1e-2, 0.3)), kappa, RT::Surface);
      add(n, m, "cone, repeated" + k, trial_strain(-3e-3, 1e-2, 0.0), kappa, RT::Surface);
      add(n, m, "apex" + k, shuffled(trial_strain(1.2e-2, 2e-3, 0.3)), kappa, RT::Apex);
    }
    add(n, m, "cone crossing kappa_r", trial_strain(-3e-3, 3e-2, 0.3), 0.012, RT::Surface);
    add(n, m, "apex crossing kappa_r", trial_strain(1.2e-2, 1.2e-2, 0.3), 0.012, RT::Apex);
  }
  return cases;
}

/// Frobenius error of a tangent against its finite-difference estimate, relative to the
/// tangent; tangents below 1e-3 of the elastic stiffness (the perfectly plastic apex, where the
/// tangent vanishes) are measured against that floor instead.
template <class Matrix>
double relative_error(const Matrix& fd, const Matrix& exact, double elastic_norm) {
  return (fd - exact).norm() / std::max(exact.norm(), 1e-3 * elastic_norm);
}

} // namespace talus::test
