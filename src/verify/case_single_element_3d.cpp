// Single-element plasticity in 3D (verification/single_element_3d.yaml): one cell of soil with
// 2 x 2 x 2 points, confined by p = 100 kPa on its x and z faces (constant tractions) and
// driven past yield by its top, so the stress is homogeneous and the material point method is
// the constitutive model along a true triaxial path. Tension is positive; c = 10 kPa,
// phi = 30 deg, Kp = (1 + sin phi) / (1 - sin phi) = 3.
//  * Mohr-Coulomb triaxial compression (associated and psi = 0): sigma_1 = Kp sigma_3 +
//    2 c sqrt(Kp) with sigma_2 = sigma_3 = -p: the stress sits on the compression edge of the
//    hexagonal pyramid, which the edge return handles (measured 1.5e-5 and 9.7e-7).
//  * Mohr-Coulomb triaxial extension (top pulled up): the two lateral stresses are the major
//    compressions, p = Kp |sigma_v| + 2 c sqrt(Kp), on the extension edge (measured 3.4e-5).
//  * Tresca: |sigma_v| - p = 2 c; von Mises: |sigma_v| - p = sigma_y (measured 8e-7, 4e-6).
//  * Drucker-Prager: the cone that matches Mohr-Coulomb in plane strain (drucker_prager.hpp:
//    alpha = tan phi / sqrt(9 + 12 tan^2 phi), k = 3 c / sqrt(9 + 12 tan^2 phi) for associated
//    flow). In triaxial compression that cone lies inside the pyramid: sqrt(J2) + alpha I1 = k
//    with sqrt(J2) = (s - p) / sqrt(3), I1 = -2 p - s gives
//    s = (k + p (1/sqrt(3) + 2 alpha)) / (1/sqrt(3) - alpha), 235.1 kPa against
//    Mohr-Coulomb's 334.6 kPa (measured 8e-6).
//  * Apex: equal extension of all three axes from a stress-free state reaches the hydrostatic
//    tip, mean stress c cot(phi) (measured 3.0e-4: the finite-strain kinematics at strains of
//    1e-4).
//  * The lateral stresses are the applied confinement: sigma_xx and sigma_zz against -p within
//    3e-4 (the traction acts on the current face, whose area strains of 1e-4 change; measured
//    3e-5 to 8e-5).
//  * Newton's order on the Mohr-Coulomb compression in two large steps: the worst step at least
//    1.8 (measured 2.11; the algorithmic tangent of the edge return; an elastic tangent
//    converges linearly).
// Each tolerance is about 3x the deviation measured for its row.
#include "cases.hpp"
#include "newton_log.hpp"

#include <array>
#include <cmath>
#include <fmt/format.h>
#include <numbers>

namespace talus::verify_cases {

namespace {

constexpr double kConfining = 1.0e5, kCohesion = 1.0e4, kPhiDegrees = 30.0;

std::string material(const std::string& model, const std::string& strength) {
  return fmt::format("materials[0]={{name: soil, model: {}, density: 2000, youngs_modulus: "
                     "1.0e10, poisson_ratio: 0.3, {}}}",
                     model, strength);
}

std::string frictional(const std::string& model, double dilation) {
  return material(model, fmt::format("cohesion: {}, friction_angle: {}, dilation_angle: {}",
                                     kCohesion, kPhiDegrees, dilation));
}

} // namespace

VerificationCase single_element_3d() {
  VerificationCase vc;
  vc.name = "single_element_3d";
  vc.description = "One 3D cell of elasto-plastic soil along true triaxial paths: Mohr-Coulomb "
                   "compression and extension edges, Tresca, von Mises, the plane-strain-matched "
                   "Drucker-Prager cone's triaxial limit, the apex; Newton's order.";
  vc.tiers = {"fast", "full"};
  vc.run = [](const VerificationContext& ctx) {
    std::vector<Check> checks;
    const double phi = kPhiDegrees * std::numbers::pi / 180.0;
    const double Kp = (1.0 + std::sin(phi)) / (1.0 - std::sin(phi));
    const double two_c_root_Kp = 2.0 * kCohesion * std::sqrt(Kp);
    const auto confinement = [&](const std::string& label, const Mat3& s) {
      for (const int d : {0, 2})
        checks.push_back(relative_check(
            fmt::format("{}: sigma_{} against the applied -p", label, d == 0 ? "xx" : "zz"),
            s(d, d), -kConfining, 3e-4, "traction on the current face; strains ~1e-4"));
    };
    for (const double psi : {kPhiDegrees, 0.0}) {
      const std::string label = fmt::format("MC triaxial compression psi={:g}", psi);
      const std::string run = fmt::format("mc_compression_psi{:g}", psi);
      const Mat3 s = final_point_stress(ctx, run, {frictional("mohr_coulomb", psi)});
      checks.push_back(relative_check(
          label + ": |sigma_v|", -s(1, 1), Kp * -s(0, 0) + two_c_root_Kp, psi > 0 ? 5e-5 : 5e-6,
          psi > 0 ? "Kp p + 2 c sqrt(Kp), the compression edge; measured 1.5e-5"
                  : "Kp p + 2 c sqrt(Kp); measured 9.7e-7"));
      confinement(label, s);
    }
    {
      // Newton's order: two load steps of 2e-4 each past yield, so that two iterates of a step
      // lie between 1e-2 and the round-off floor (with the 20 small steps above, the last
      // iterate already reaches round-off, which says nothing about the order).
      const std::string run = "mc_newton";
      final_point_stress(ctx, run,
                         {frictional("mohr_coulomb", kPhiDegrees), "time.dt=0.5",
                          "prescribed[0].displacement=[~, -4.0e-4, ~]"});
      checks.push_back(newton_order_check("MC triaxial compression: Newton order (worst step)",
                                          ctx.out_dir / run / "newton.log", 1.8,
                                          "edge return's algorithmic tangent; measured 2.11"));
    }
    {
      const Mat3 s = final_point_stress(
          ctx, "mc_extension",
          {frictional("mohr_coulomb", kPhiDegrees), "prescribed[0].displacement=[~, 1.0e-4, ~]"});
      checks.push_back(relative_check(
          "MC triaxial extension: |sigma_v|", -s(1, 1), (-s(0, 0) - two_c_root_Kp) / Kp, 1e-4,
          "p = Kp |sigma_v| + 2 c sqrt(Kp), the extension edge; measured 3.4e-5"));
      confinement("MC triaxial extension", s);
    }
    {
      const Mat3 s = final_point_stress(ctx, "tresca", {material("tresca", "cohesion: 1.0e4")});
      checks.push_back(relative_check("Tresca triaxial: sigma_h - sigma_v", s(0, 0) - s(1, 1),
                                      2.0 * kCohesion, 3e-6, "2 c; measured 8e-7"));
      confinement("Tresca triaxial", s);
    }
    {
      const double sigma_y = 1.0e5;
      const Mat3 s =
          final_point_stress(ctx, "von_mises", {material("von_mises", "yield_stress: 1.0e5")});
      checks.push_back(relative_check("von Mises triaxial: sigma_h - sigma_v", s(0, 0) - s(1, 1),
                                      sigma_y, 1.5e-5, "q = sigma_y; measured 4e-6"));
    }
    {
      const double root = std::sqrt(9.0 + 12.0 * std::tan(phi) * std::tan(phi));
      const double alpha = std::tan(phi) / root, k = 3.0 * kCohesion / root;
      const double inv3 = 1.0 / std::sqrt(3.0);
      const Mat3 s =
          final_point_stress(ctx, "drucker_prager", {frictional("drucker_prager", kPhiDegrees)});
      const double p = -s(0, 0);
      checks.push_back(
          relative_check("DP (plane-strain match) triaxial compression: |sigma_v|", -s(1, 1),
                         (k + p * (inv3 + 2.0 * alpha)) / (inv3 - alpha), 3e-5,
                         "the cone inside the pyramid: 0.70 of Mohr-Coulomb's; measured 8e-6"));
      confinement("DP triaxial compression", s);
    }
    {
      // Each node of the cell off the lower faces moves out by 1e-4 along the axes on which it
      // lies at 1 (one box per node: the first box that holds a node prescribes it).
      std::string boxes;
      for (int pattern = 1; pattern < 8; ++pattern) {
        std::array<int, 3> at{};
        std::string u;
        for (int d = 0; d < 3; ++d) {
          at[static_cast<std::size_t>(d)] = (pattern >> d) & 1;
          u += std::string(d ? ", " : "") + (at[static_cast<std::size_t>(d)] ? "1.0e-4" : "~");
        }
        boxes += fmt::format("{}{{name: n{}, min: [{}, {}, {}], max: [{}, {}, {}], displacement: "
                             "[{}]}}",
                             pattern > 1 ? ", " : "", pattern, 0.9 * at[0], 0.9 * at[1],
                             0.9 * at[2], at[0] + 0.1, at[1] + 0.1, at[2] + 0.1, u);
      }
      const Mat3 s =
          final_point_stress(ctx, "apex",
                             {frictional("mohr_coulomb", kPhiDegrees), "bodies[0].initial_stress=~",
                              "tractions=~", "prescribed=[" + boxes + "]"});
      checks.push_back(relative_check("MC apex: mean stress", s.trace() / 3.0,
                                      kCohesion / std::tan(phi), 9e-4,
                                      "c cot(phi); measured 3.0e-4"));
    }
    return checks;
  };
  return vc;
}

} // namespace talus::verify_cases
