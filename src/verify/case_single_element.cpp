// Single-element plasticity: one grid cell of soil with 2 x 2 material points whose GIMP domains
// fill the cell, so that deformation and stress are homogeneous and the material point method
// reduces to the constitutive model driven along a plane-strain path (verification/
// single_element.yaml). Each run is pushed well past yield with perfect plasticity; the stress
// it settles on is compared with the closed-form limit to 0.1 %. Tension is positive; p = 100
// kPa confining, c = 10 kPa, phi = 30 deg (Kp = (1 + sin phi) / (1 - sin phi) = 3).
//  * Mohr-Coulomb plane-strain compression (associated and psi = 0): |sigma_v| = Kp p + 2 c
//    sqrt(Kp) — valid because the out-of-plane stress stays the intermediate one (checked).
//  * Mohr-Coulomb plane-strain extension: the lateral stress is now the major compression,
//    p = Kp |sigma_v| + 2 c sqrt(Kp).
//  * Tresca compression: |sigma_v| - p = 2 c.
//  * Drucker-Prager with the plane-strain match to Mohr-Coulomb (associated): the same
//    plane-strain compression limit as Mohr-Coulomb, which is what the match promises.
//  * Apex: equal in-plane extension from a stress-free state reaches the hydrostatic tip,
//    mean stress c cot(phi).
//  * von Mises simple shear: tau_xy = sigma_y / sqrt(3).
// The strains stay near 1e-4 (E = 1e10), so the finite-strain kinematics differ from the
// small-strain limit forms by far less than the tolerance.
#include "cases.hpp"

#include <cmath>
#include <fmt/format.h>
#include <numbers>

namespace talus::verify_cases {

namespace {

constexpr double kConfining = 1.0e5, kCohesion = 1.0e4, kPhiDegrees = 30.0;
constexpr double kTolerance = 1e-3;

/// Final Cauchy stress of the first point (all four are equal), from a run with overrides.
Mat3 final_stress(const VerificationContext& ctx, const std::string& run,
                  const std::vector<std::string>& overrides) {
  const auto dir = ctx.out_dir / run;
  run_quiet(load_verification_case(ctx, overrides), dir, ctx.threads);
  const ResultsReader results(dir / "run.h5");
  Index rows = 0, cols = 0;
  const auto s = results.read(results.frame_count() - 1, "stress", &rows, &cols);
  // XDMF Tensor6 order: xx, xy, xz, yy, yz, zz
  Mat3 sigma;
  sigma << s[0], s[1], s[2], s[1], s[3], s[4], s[2], s[4], s[5];
  return sigma;
}

std::string mohr_coulomb(double dilation) {
  return fmt::format("materials[0]={{name: soil, model: mohr_coulomb, density: 2000, "
                     "youngs_modulus: 1.0e10, poisson_ratio: 0.3, cohesion: {}, "
                     "friction_angle: {}, dilation_angle: {}}}",
                     kCohesion, kPhiDegrees, dilation);
}

} // namespace

VerificationCase single_element() {
  VerificationCase vc;
  vc.name = "single_element";
  vc.description = "One cell of elasto-plastic soil driven past yield along plane-strain paths: "
                   "Mohr-Coulomb compression and extension limits, Tresca 2c, the Drucker-Prager "
                   "plane-strain match, the Mohr-Coulomb apex c cot(phi), von Mises shear "
                   "sigma_y/sqrt(3), each to 0.1 %.";
  vc.tiers = {"fast", "full"};
  vc.run = [](const VerificationContext& ctx) {
    std::vector<Check> checks;
    const double phi = kPhiDegrees * std::numbers::pi / 180.0;
    const double Kp = (1.0 + std::sin(phi)) / (1.0 - std::sin(phi));
    const double two_c_root_Kp = 2.0 * kCohesion * std::sqrt(Kp);

    auto compression_check = [&](const std::string& label, const Mat3& s, double limit) {
      checks.push_back(relative_check(label + ": |sigma_v|", -s(1, 1), limit, kTolerance,
                                      fmt::format("sigma_h = {:.6g} Pa", s(0, 0))));
    };
    for (const double psi : {kPhiDegrees, 0.0}) {
      const Mat3 s =
          final_stress(ctx, fmt::format("mc_compression_psi{:g}", psi), {mohr_coulomb(psi)});
      compression_check(fmt::format("MC compression psi={:g}", psi), s,
                        Kp * -s(0, 0) + two_c_root_Kp);
      checks.push_back(bound_check(
          fmt::format("MC compression psi={:g}: sigma_zz intermediate", psi),
          (s(2, 2) - s(1, 1)) * (s(2, 2) - s(0, 0)), 0.0, "(szz - syy)(szz - sxx) <= 0"));
    }
    {
      const Mat3 s =
          final_stress(ctx, "mc_extension",
                       {mohr_coulomb(kPhiDegrees), "prescribed[0].displacement=[~, 1.0e-4]"});
      checks.push_back(relative_check("MC extension: |sigma_v|", -s(1, 1),
                                      (-s(0, 0) - two_c_root_Kp) / Kp, kTolerance,
                                      "p = Kp |sigma_v| + 2 c sqrt(Kp)"));
    }
    {
      const Mat3 s = final_stress(ctx, "tresca",
                                  {"materials[0]={name: soil, model: tresca, density: 2000, "
                                   "youngs_modulus: 1.0e10, poisson_ratio: 0.3, cohesion: 1.0e4}"});
      checks.push_back(relative_check("Tresca compression: sigma_h - sigma_v", s(0, 0) - s(1, 1),
                                      2.0 * kCohesion, kTolerance, "2 c"));
    }
    {
      const Mat3 s = final_stress(
          ctx, "drucker_prager",
          {fmt::format("materials[0]={{name: soil, model: drucker_prager, density: 2000, "
                       "youngs_modulus: 1.0e10, poisson_ratio: 0.3, cohesion: {}, "
                       "friction_angle: {}, dilation_angle: {}}}",
                       kCohesion, kPhiDegrees, kPhiDegrees)});
      compression_check("DP (plane-strain match) compression", s, Kp * -s(0, 0) + two_c_root_Kp);
    }
    {
      // Stress-free start, right and top faces pulled out equally.
      const Mat3 s = final_stress(
          ctx, "apex",
          {mohr_coulomb(kPhiDegrees), "bodies[0].initial_stress=~", "tractions=~",
           "prescribed=[{name: corner, min: [0.9, 0.9], max: [1.1, 1.1], displacement: [1.0e-4, "
           "1.0e-4]}, {name: right, min: [0.9, 0], max: [1.1, 0.1], displacement: [1.0e-4, ~]}, "
           "{name: top, min: [0, 0.9], max: [0.1, 1.1], displacement: [~, 1.0e-4]}]"});
      const double apex = kCohesion / std::tan(phi);
      checks.push_back(
          relative_check("MC apex: mean stress", s.trace() / 3.0, apex, kTolerance, "c cot(phi)"));
      checks.push_back(bound_check("MC apex: deviator / (c cot phi)",
                                   (s - s.trace() / 3.0 * Mat3::Identity()).norm() / apex,
                                   kTolerance, "hydrostatic"));
    }
    {
      const double sigma_y = 1.0e5;
      const Mat3 s = final_stress(
          ctx, "von_mises_shear",
          {"materials[0]={name: soil, model: von_mises, density: 2000, youngs_modulus: 1.0e10, "
           "poisson_ratio: 0.3, yield_stress: 1.0e5}",
           "bodies[0].initial_stress=~", "tractions=~", "boundaries={y_min: fixed}",
           "prescribed[0].displacement=[1.0e-4, 0]"});
      checks.push_back(relative_check("von Mises simple shear: tau_xy", s(0, 1),
                                      sigma_y / std::sqrt(3.0), kTolerance, "sigma_y / sqrt(3)"));
    }
    return checks;
  };
  return vc;
}

} // namespace talus::verify_cases
