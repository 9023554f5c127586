// Principal-space return maps (von Mises, Tresca, Mohr-Coulomb, Drucker-Prager, softening): the
// 3x3 consistent tangent against central finite differences for every model and return type,
// the returned state (on the surface, flow rule, kappa definition, stored elastic strain),
// closed-form limit states, order independence and parameter validation.
#include "talus/core/errors.hpp"
#include "test_plasticity_cases.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

using namespace talus;
using talus::test::kSoilLame;
using talus::test::return_cases;
using talus::test::ReturnCase;

namespace {

constexpr double kDegree = std::numbers::pi / 180.0;

Vec3 sorted_descending(Vec3 v) {
  std::sort(v.data(), v.data() + 3, [](double a, double b) { return a > b; });
  return v;
}

/// Stress scale of a case: the largest trial stress plus the cohesion-like strength.
double stress_scale(const ReturnCase& c) {
  return c.model->elastic_stress(c.trial).cwiseAbs().maxCoeff() + 2.0e4;
}

} // namespace

TEST(PlasticityReturnMap, EveryCaseHitsItsReturnType) {
  for (const auto& c : return_cases()) {
    SCOPED_TRACE(c.name);
    EXPECT_EQ(to_string(c.model->return_map(c.trial, c.kappa).type), to_string(c.expected));
  }
}

// Central differences with step h = 1e-5 |eps^tr|_max. The maps are piecewise smooth with
// curvature on the scale of the strains themselves (cone and cylinder radius, softening through
// kappa), so truncation is ~(h / |eps|)^2 = 1e-10; round-off in the stress difference is
// ~eps_mach |sigma| / (h |D|) ~ 1e-11; the local Newton's residual tolerance (1e-13 of the
// stress scale) adds ~1e-8. Each case sits at least ~1e-3 in strain from a region boundary, far
// beyond h ~ 1e-7, so the differences never straddle two returns.
TEST(PlasticityReturnMap, TangentMatchesFiniteDifferences) {
  double worst = 0;
  for (const auto& c : return_cases()) {
    SCOPED_TRACE(c.name);
    const PrincipalReturn r = c.model->return_map(c.trial, c.kappa);
    ASSERT_EQ(r.type, c.expected);
    const double h = 1e-5 * c.trial.cwiseAbs().maxCoeff();
    Mat3 fd;
    for (int b = 0; b < 3; ++b) {
      Vec3 plus = c.trial, minus = c.trial;
      plus(b) += h;
      minus(b) -= h;
      const PrincipalReturn rp = c.model->return_map(plus, c.kappa);
      const PrincipalReturn rm = c.model->return_map(minus, c.kappa);
      ASSERT_EQ(rp.type, c.expected);
      ASSERT_EQ(rm.type, c.expected);
      fd.col(b) = (rp.stress - rm.stress) / (2.0 * h);
    }
    const double err = test::relative_error(fd, r.tangent, c.model->elastic_stiffness().norm());
    std::printf("[ fd ] %-72s %.1e\n", c.name.c_str(), err);
    EXPECT_LT(err, 1e-6);
    worst = std::max(worst, err);
  }
  std::printf("[ fd ] principal tangents, worst relative error %.1e\n", worst);
}

TEST(PlasticityReturnMap, ReturnedStateIsConsistent) {
  for (const auto& c : return_cases()) {
    SCOPED_TRACE(c.name);
    const PrincipalReturn r = c.model->return_map(c.trial, c.kappa);
    const double scale = stress_scale(c);
    // the stored elastic strain carries the returned stress
    EXPECT_LT((c.model->elastic_stress(r.elastic_strain) - r.stress).norm(), 1e-12 * scale);
    if (r.type == ReturnType::Elastic) {
      EXPECT_LE(c.model->yield_function(r.stress, c.kappa), 0.0);
      EXPECT_EQ(r.kappa, c.kappa);
      continue;
    }
    // on the yield surface at the updated kappa, and kappa grew by sqrt(2/3) |dev(deps^p)|
    EXPECT_LT(std::abs(c.model->yield_function(r.stress, r.kappa)), 1e-12 * scale);
    const Vec3 dep = c.trial - r.elastic_strain;
    EXPECT_NEAR(r.kappa - c.kappa, std::sqrt(2.0 / 3.0) * deviator(dep).norm(),
                1e-12 * c.trial.norm());
    EXPECT_GE(r.kappa, c.kappa); // equal only for a purely hydrostatic apex return
  }
}

TEST(PlasticityReturnMap, OutputFollowsTheInputOrder) {
  for (const auto& c : return_cases()) {
    SCOPED_TRACE(c.name);
    const PrincipalReturn r = c.model->return_map(c.trial, c.kappa);
    // reversed input: every output is reversed too
    const Eigen::PermutationMatrix<3> P(Eigen::Vector3i(2, 1, 0));
    const PrincipalReturn q = c.model->return_map(P * c.trial, c.kappa);
    const double scale = stress_scale(c);
    EXPECT_LT((q.stress - P * r.stress).norm(), 1e-12 * scale);
    EXPECT_LT((q.tangent - P * r.tangent * P.transpose()).norm(),
              1e-12 * c.model->elastic_stiffness().norm());
    EXPECT_EQ(q.type, r.type);
  }
}

// The flow rule: the plastic strain increment is a non-negative combination of the potential's
// gradients at the returned state, computed here from the model parameters independently of the
// implementation.
TEST(PlasticityReturnMap, PlasticFlowFollowsTheFlowRule) {
  for (const auto& c : return_cases()) {
    const PrincipalReturn r = c.model->return_map(c.trial, c.kappa);
    if (r.type == ReturnType::Elastic || r.type == ReturnType::Apex)
      continue;
    SCOPED_TRACE(c.name);
    // sorted frame of the trial strain (stress and strain share the order)
    const Vec3 eps = sorted_descending(c.trial);
    const PrincipalReturn s = c.model->return_map(eps, c.kappa);
    const Vec3 dep = eps - s.elastic_strain;
    Eigen::Matrix<double, 3, 2> G = Eigen::Matrix<double, 3, 2>::Zero();
    int columns = 1;
    if (const auto* mc = dynamic_cast<const MohrCoulomb*>(c.model.get())) {
      const double sp = std::sin(mc->strength().dilation());
      G.col(0) = Vec3(1.0 + sp, 0.0, -(1.0 - sp));
      if (s.type == ReturnType::CompressionEdge) {
        G.col(1) = Vec3(0.0, 1.0 + sp, -(1.0 - sp));
        columns = 2;
      } else if (s.type == ReturnType::ExtensionEdge) {
        G.col(1) = Vec3(1.0 + sp, -(1.0 - sp), 0.0);
        columns = 2;
      }
    } else if (const auto* dp = dynamic_cast<const DruckerPrager*>(c.model.get())) {
      const Vec3 n = deviator(s.stress).normalized();
      G.col(0) = n / std::sqrt(2.0) + Vec3::Constant(dp->coefficients(s.kappa).alpha_flow);
    } else { // von Mises: radial
      G.col(0) = deviator(s.stress).normalized();
    }
    const auto Gc = G.leftCols(columns);
    const Eigen::VectorXd gamma = Gc.colPivHouseholderQr().solve(dep);
    EXPECT_LT((Gc * gamma - dep).norm(), 1e-10 * dep.norm());
    EXPECT_GE(gamma.minCoeff(), 0.0);
  }
}

// Closed-form checks. A driver holds the lateral stresses of a triaxial test at -p_c and
// solves for the lateral strain with Newton on the algorithmic tangent (quadratic convergence is
// a second check of the tangent), in one large strain step from the unstrained state.
namespace {

struct TriaxialResult {
  Vec3 stress;
  int iterations;
  ReturnType type;
};

/// Axial strain eps_axial (index 0), lateral strains equal (indices 1, 2), lateral stress -p_c.
TriaxialResult triaxial(const PlasticModel& m, double eps_axial, double p_c) {
  // start from the elastic lateral strain: lambda (e_a + 2 e_l) + 2 mu e_l = -p_c
  const LameParameters& l = m.lame();
  double lateral = (-p_c - l.lambda * eps_axial) / (2.0 * (l.lambda + l.mu));
  for (int it = 0; it < 30; ++it) {
    const PrincipalReturn r = m.return_map(Vec3(eps_axial, lateral, lateral), 0.0);
    const double residual = r.stress(1) + p_c;
    if (std::abs(residual) < 1e-10 * (p_c + 1e4))
      return {r.stress, it, r.type};
    lateral -= residual / (r.tangent(1, 1) + r.tangent(1, 2));
  }
  return {Vec3::Constant(NAN), 30, ReturnType::Elastic};
}

} // namespace

TEST(PlasticityClosedForm, MohrCoulombTriaxialCompressionExtensionAndApex) {
  const double c = 2.0e4, phi = 30.0, p_c = 2.0e5;
  const double sp = std::sin(phi * kDegree);
  const double Kp = (1.0 + sp) / (1.0 - sp);
  for (const double psi : {30.0, 10.0, 0.0}) {
    SCOPED_TRACE(psi);
    const MohrCoulomb m(kSoilLame, test::mc(c, phi, psi));
    // compression: |sigma_3| = K_p p_c + 2 c sqrt(K_p)
    const TriaxialResult tc = triaxial(m, -0.03, p_c);
    EXPECT_EQ(tc.type, ReturnType::CompressionEdge);
    EXPECT_LE(tc.iterations, 8);
    EXPECT_NEAR(-tc.stress(0), Kp * p_c + 2.0 * c * std::sqrt(Kp), 1e-9 * p_c);
    // extension (axial the least compressive): p_c = K_p |sigma_1| + 2 c sqrt(K_p)
    const TriaxialResult te = triaxial(m, 0.01, p_c);
    EXPECT_EQ(te.type, ReturnType::ExtensionEdge);
    EXPECT_LE(te.iterations, 8);
    EXPECT_NEAR(-te.stress(0), (p_c - 2.0 * c * std::sqrt(Kp)) / Kp, 1e-9 * p_c);
    // apex: hydrostatic tension beyond c cot(phi) returns to it
    const PrincipalReturn apex = m.return_map(Vec3::Constant(0.01), 0.0);
    EXPECT_EQ(apex.type, ReturnType::Apex);
    EXPECT_LT((apex.stress - Vec3::Constant(c / std::tan(phi * kDegree))).norm(), 1e-9 * c);
  }
}

TEST(PlasticityClosedForm, TrescaUniaxialAndPureShear) {
  const double c = 2.0e4;
  const Tresca m(kSoilLame, c);
  // unconfined compression: |sigma| = 2 c
  const TriaxialResult uc = triaxial(m, -0.03, 0.0);
  EXPECT_EQ(uc.type, ReturnType::CompressionEdge);
  EXPECT_NEAR(uc.stress(0), -2.0 * c, 1e-9 * c);
  // pure shear strain (e, 0, -e): sigma = (c, 0, -c) from the plane return
  const PrincipalReturn shear = m.return_map(Vec3(0.01, 0.0, -0.01), 0.0);
  EXPECT_EQ(shear.type, ReturnType::Surface);
  EXPECT_LT((shear.stress - Vec3(c, 0.0, -c)).norm(), 1e-9 * c);
}

TEST(PlasticityClosedForm, VonMisesShearAndUniaxialYield) {
  const double sigma_y = 4.0e4;
  const VonMises m(kSoilLame, sigma_y);
  // pure shear: tau = sigma_y / sqrt(3)
  const PrincipalReturn shear = m.return_map(Vec3(0.01, -0.01, 0.0), 0.0);
  EXPECT_EQ(shear.type, ReturnType::Surface);
  EXPECT_LT((shear.stress - Vec3(1.0, -1.0, 0.0) * sigma_y / std::sqrt(3.0)).norm(),
            1e-9 * sigma_y);
  // uniaxial: |sigma| = sigma_y
  const TriaxialResult uc = triaxial(m, -0.03, 0.0);
  EXPECT_NEAR(uc.stress(0), -sigma_y, 1e-9 * sigma_y);
  // linear hardening: sigma_y(kappa) = sigma_y0 + H kappa at the returned kappa
  const VonMises hard(kSoilLame, sigma_y, 2.0e6);
  const PrincipalReturn h = hard.return_map(Vec3(0.01, -0.01, 0.0), 0.0);
  EXPECT_NEAR(std::sqrt(1.5) * deviator(h.stress).norm(), sigma_y + 2.0e6 * h.kappa,
              1e-9 * sigma_y);
}

TEST(PlasticityClosedForm, DruckerPragerApexIsMohrCoulombApex) {
  for (const double psi : {30.0, 10.0, 0.0}) {
    const DruckerPrager m(kSoilLame, test::mc(2.0e4, 30.0, psi));
    const PrincipalReturn apex = m.return_map(Vec3::Constant(0.01), 0.0);
    EXPECT_EQ(apex.type, ReturnType::Apex);
    EXPECT_LT((apex.stress - Vec3::Constant(2.0e4 / std::tan(30.0 * kDegree))).norm(), 1e-9 * 2e4);
  }
}

// The plane-strain match: at a Mohr-Coulomb limit state whose out-of-plane stress makes the
// cone's out-of-plane plastic strain rate vanish, the cone is at yield too.
TEST(PlasticityDruckerPragerMatch, ConeMeetsMohrCoulombInPlaneStrain) {
  for (const double phi : {10.0, 30.0, 45.0})
    for (const double psi : {0.0, 0.5 * phi, phi}) {
      SCOPED_TRACE(::testing::Message() << "phi " << phi << " psi " << psi);
      const double c = 1.5e4;
      const DruckerPragerMatch m = plane_strain_match(c, phi * kDegree, psi * kDegree);
      const DruckerPrager dp(kSoilLame, test::mc(c, phi, psi));
      for (const double mean : {-1e5, -2e4, 0.0}) {
        const double t = c * std::cos(phi * kDegree) - mean * std::sin(phi * kDegree);
        const double d =
            -3.0 * m.alpha_flow * t / std::sqrt(1.0 - 3.0 * m.alpha_flow * m.alpha_flow);
        const Vec3 sigma(mean + t, mean - t, mean + d); // in plane: 1, 2; out of plane: 3
        EXPECT_NEAR(dp.yield_function(sigma, 0.0), 0.0, 1e-10 * (c + std::abs(mean)));
        const Vec3 s = deviator(sigma);
        const double flow_zz = s(2) / (std::sqrt(2.0) * s.norm()) + m.alpha_flow;
        EXPECT_NEAR(flow_zz, 0.0, 1e-12);
      }
      if (psi == phi) { // the classical associated formulas
        const double tp = std::tan(phi * kDegree), root = std::sqrt(9.0 + 12.0 * tp * tp);
        EXPECT_NEAR(m.alpha, tp / root, 1e-15);
        EXPECT_NEAR(m.k, 3.0 * c / root, 1e-10 * c);
      }
    }
}

TEST(PlasticitySoftening, StrengthIsPiecewiseLinear) {
  const FrictionalStrength s(test::softening());
  EXPECT_DOUBLE_EQ(s.at(0.0).cohesion, 2.0e4);
  EXPECT_DOUBLE_EQ(s.at(0.01).cohesion, 1.25e4);
  EXPECT_NEAR(s.at(0.01).friction, 30.0 * kDegree, 1e-15);
  EXPECT_DOUBLE_EQ(s.at(0.01).cohesion_slope, -1.5e4 / 0.02);
  EXPECT_DOUBLE_EQ(s.at(0.05).cohesion, 5.0e3);
  EXPECT_EQ(s.at(0.05).friction_slope, 0.0);
}

// The softening cases really exercise what their names say: kappa stays on the softening branch,
// crosses kappa_r within the step, or starts on the residual plateau.
TEST(PlasticitySoftening, CasesCoverBranchesAndTheCrossing) {
  int crossing = 0;
  for (const auto& c : return_cases()) {
    if (c.name.find("softening:") == std::string::npos)
      continue;
    SCOPED_TRACE(c.name);
    const PrincipalReturn r = c.model->return_map(c.trial, c.kappa);
    if (c.name.find("crossing") != std::string::npos) {
      EXPECT_LT(c.kappa, 0.02);
      EXPECT_GT(r.kappa, 0.02 + 1e-4);
      ++crossing;
    } else if (c.name.find("softening branch") != std::string::npos) {
      EXPECT_LT(r.kappa, 0.02 - 1e-4);
    } else {
      EXPECT_GT(c.kappa, 0.02);
    }
  }
  EXPECT_EQ(crossing, 5);
}

// Softening makes the tangent nonsymmetric (the plane normal differs from the flow direction
// through kappa even for associated flow); perfect associated plasticity keeps it symmetric.
TEST(PlasticitySoftening, TangentSymmetry) {
  const Vec3 eps = test::trial_strain(-3e-3, 8e-3, 0.5);
  const MohrCoulomb associated(kSoilLame, test::mc(2e4, 30.0, 30.0));
  const Mat3 Ta = associated.return_map(eps, 0.0).tangent;
  EXPECT_LT((Ta - Ta.transpose()).norm(), 1e-12 * Ta.norm());
  FrictionalStrengthParameters p = test::softening();
  p.dilation_angle = 25.0;
  const MohrCoulomb soft(kSoilLame, p);
  const Mat3 Ts = soft.return_map(eps, 0.005).tangent;
  EXPECT_GT((Ts - Ts.transpose()).norm(), 1e-3 * Ts.norm());
}

TEST(PlasticityParameters, BadParametersThrow) {
  EXPECT_THROW(checked_lame_parameters(0.0, 0.3), InputError);
  EXPECT_THROW(checked_lame_parameters(1e7, 0.5), InputError);
  EXPECT_THROW(checked_lame_parameters(1e7, -1.0), InputError);
  EXPECT_NO_THROW(checked_lame_parameters(1e7, 0.49));
  EXPECT_THROW(VonMises(LameParameters{1e7, -1e6}, 1e4), InputError); // mu <= 0
  EXPECT_THROW(VonMises(LameParameters{-1e7, 1e6}, 1e4), InputError); // K <= 0
  EXPECT_THROW(VonMises(kSoilLame, 0.0), InputError);
  EXPECT_THROW(VonMises(kSoilLame, 1e4, -1.0), InputError);
  EXPECT_THROW(Tresca(kSoilLame, 0.0), InputError);
  EXPECT_THROW(Tresca(kSoilLame, -1.0), InputError);
  auto bad = [](FrictionalStrengthParameters p, const char* key) {
    SCOPED_TRACE(key);
    try {
      MohrCoulomb m(kSoilLame, p);
      ADD_FAILURE() << "no exception";
    } catch (const InputError& e) {
      EXPECT_EQ(e.where().key_path, key);
    }
    EXPECT_THROW(DruckerPrager(kSoilLame, p), InputError);
  };
  bad(test::mc(-1.0, 30.0, 0.0), "cohesion");
  bad(test::mc(1e4, 90.0, 0.0), "friction_angle");
  bad(test::mc(1e4, -1.0, 0.0), "friction_angle");
  bad(test::mc(1e4, 30.0, 31.0), "dilation_angle");
  bad(test::mc(1e4, 30.0, -1.0), "dilation_angle");
  bad(test::mc(0.0, 0.0, 0.0), "cohesion");
  auto soft = test::softening();
  soft.residual->kappa = 0.0;
  bad(soft, "residual.kappa");
  soft = test::softening();
  soft.residual->friction_angle = 4.0; // below psi = 5
  bad(soft, "dilation_angle");
  soft = test::softening();
  soft.dilation_angle = 0.0;
  soft.residual->friction_angle = 0.0; // apex would run off to infinity
  bad(soft, "residual.friction_angle");
  soft = test::softening();
  soft.residual->cohesion = -1.0;
  bad(soft, "residual.cohesion");
}
