// Kinematic wrappers of the return maps (elastoplastic_response.hpp): the 9x9 dtau/dF of the
// finite-strain (exponential map) and small-strain updates against central finite differences
// for every model and return type, in 3D and in plane strain, from a converged state with
// plastic history and a general F_n; elastic steps against hencky_response and
// linear_elastic_response; objectivity; the stored history; failures.
#include "talus/core/errors.hpp"
#include "talus/material/hyperelastic.hpp"
#include "talus/material/plasticity/elastoplastic_response.hpp"
#include "test_plasticity_cases.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

using namespace talus;
using talus::test::kSoilLame;
using talus::test::return_cases;
using talus::test::ReturnCase;

namespace {

Mat3 rotation(double angle, const Vec3& axis) {
  return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

Mat2 rotation2(double angle) {
  Mat2 R;
  R << std::cos(angle), -std::sin(angle), std::sin(angle), std::cos(angle);
  return R;
}

Mat3 sym(const Mat3& A) {
  return 0.5 * (A + A.transpose());
}

const Mat3 kR = rotation(0.7, Vec3(1.0, 2.0, -0.5));
const Mat3 kQ = rotation(-1.1, Vec3(-0.3, 0.4, 1.0));

/// One step: the converged state (F_old, history) and the trial gradient F_new.
struct Step {
  Mat3 F_old, F_new;
  PlasticHistory converged;
};

/// A step whose trial elastic strain has principal values `eps` (any order) and the converged
/// kappa `kappa`, with a general F_n and a non-trivial converged elastic state. Plane strain:
/// F_33 = 1 throughout and eps(out_of_plane) is the out-of-plane trial strain (carried by the
/// history, since F_33 = 1 adds nothing); the other two are in-plane.
Step make_step(Kinematics kind, const Vec3& eps, double kappa, bool plane, int out_of_plane) {
  Step s;
  s.converged.kappa = kappa;
  const Vec3 hist(1e-3, -2e-3, 5e-4); // principal elastic strain of the converged state
  if (!plane) {
    s.F_old = rotation(0.4, Vec3(0.3, -1.0, 0.2)) * Vec3(1.1, 0.95, 1.02).asDiagonal() *
              rotation(-0.8, Vec3(1.0, 0.1, 0.5));
    const Mat3 R1 = rotation(1.3, Vec3(0.5, 0.5, -1.0));
    if (kind == Kinematics::FiniteStrain) {
      s.converged.elastic = R1 * (2.0 * hist).array().exp().matrix().asDiagonal() * R1.transpose();
      // b_e^tr = F A F^T with A = L L^T: F = R exp(eps) Q L^{-1} gives b_e^tr = R exp(2 eps) R^T
      const Mat3 Finv = s.F_old.inverse();
      const Mat3 A = Finv * s.converged.elastic * Finv.transpose();
      const Mat3 L = A.llt().matrixL();
      s.F_new = kR * eps.array().exp().matrix().asDiagonal() * kQ * L.inverse();
    } else {
      s.F_old = Mat3::Identity() + 0.02 * Mat3{{0.5, 1.0, -0.3}, {0.2, -0.7, 0.4}, {0.9, 0.1, 0.3}};
      s.converged.elastic = R1 * hist.asDiagonal() * R1.transpose();
      const Mat3 target = kR * eps.asDiagonal() * kR.transpose();
      const Mat3 W = 0.03 * Mat3{{0.0, 1.0, -0.5}, {-1.0, 0.0, 0.7}, {0.5, -0.7, 0.0}};
      s.F_new = target - s.converged.elastic + sym(s.F_old) + W;
    }
    return s;
  }
  // plane strain
  const int a = (out_of_plane + 1) % 3, b = (out_of_plane + 2) % 3;
  const Vec2 in_plane(eps(a), eps(b));
  const Mat2 F2_old = rotation2(0.3) * Mat2{{1.1, 0.05}, {0.0, 0.95}};
  s.F_old = embedded<2>(F2_old);
  const Mat2 R2 = rotation2(0.5);
  if (kind == Kinematics::FiniteStrain) {
    const Mat2 b2 = R2 * Vec2(std::exp(2e-3), std::exp(-4e-3)).asDiagonal() * R2.transpose();
    s.converged.elastic = Mat3::Identity();
    s.converged.elastic.topLeftCorner<2, 2>() = b2;
    s.converged.elastic(2, 2) = std::exp(2.0 * eps(out_of_plane));
    const Mat2 Finv = F2_old.inverse();
    const Mat2 A = Finv * b2 * Finv.transpose();
    const Mat2 L = A.llt().matrixL();
    s.F_new = embedded<2>(rotation2(-0.9) * in_plane.array().exp().matrix().asDiagonal() *
                          rotation2(0.6) * L.inverse());
  } else {
    s.F_old = embedded<2>(Mat2::Identity() + 0.02 * Mat2{{0.5, 1.0}, {0.2, -0.7}});
    s.converged.elastic = Mat3::Zero();
    s.converged.elastic.topLeftCorner<2, 2>() =
        R2 * Vec2(1e-3, -2e-3).asDiagonal() * R2.transpose();
    s.converged.elastic(2, 2) = eps(out_of_plane);
    const Mat2 target = rotation2(-0.9) * in_plane.asDiagonal() * rotation2(-0.9).transpose();
    const Mat2 W{{0.0, 0.03}, {-0.03, 0.0}};
    const Mat2 sym_old =
        0.5 * (s.F_old.topLeftCorner<2, 2>() + s.F_old.topLeftCorner<2, 2>().transpose());
    s.F_new = embedded<2>(target - s.converged.elastic.topLeftCorner<2, 2>() + sym_old + W);
  }
  return s;
}

const char* kind_name(Kinematics kind) {
  return kind == Kinematics::FiniteStrain ? "finite" : "small";
}

} // namespace

// Central differences in F_new with step h = 1e-5 |eps^tr|_max, the same ratio to the strain
// scale as the principal test (truncation ~1e-10, round-off ~1e-11 relative to the tangent):
// F's entries are O(1) but tau varies on the scale of the trial strains. Plane strain perturbs
// only the in-plane components of F (F_33 = 1) and checks those four columns.
TEST(PlasticityKinematics, TangentMatchesFiniteDifferences) {
  struct Layout {
    const char* name;
    bool plane;
    int out_of_plane;
  };
  const Layout layouts[] = {
      {"3D", false, 0}, {"plane strain (zz = 3rd)", true, 2}, {"plane strain (zz = 1st)", true, 0}};
  for (const Kinematics kind : {Kinematics::FiniteStrain, Kinematics::SmallStrain})
    for (const Layout& layout : layouts) {
      double worst = 0;
      for (const ReturnCase& c : return_cases()) {
        SCOPED_TRACE(::testing::Message()
                     << kind_name(kind) << ", " << layout.name << ": " << c.name);
        const Step s = make_step(kind, c.trial, c.kappa, layout.plane, layout.out_of_plane);
        PlasticHistory updated;
        ReturnType type{};
        const StressTangent r =
            elastoplastic_response(*c.model, kind, s.F_new, s.F_old, s.converged, updated, &type);
        ASSERT_EQ(to_string(type), to_string(c.expected));
        const double h = 1e-5 * c.trial.cwiseAbs().maxCoeff();
        std::vector<int> columns;
        for (int k = 0; k < 3; ++k)
          for (int l = 0; l < 3; ++l)
            if (!layout.plane || (k < 2 && l < 2))
              columns.push_back(flat_index(k, l));
        Eigen::MatrixXd fd(9, columns.size()), exact(9, columns.size());
        for (std::size_t j = 0; j < columns.size(); ++j) {
          const int kl = columns[j];
          Mat3 Fp = s.F_new, Fm = s.F_new;
          Fp(kl / 3, kl % 3) += h;
          Fm(kl / 3, kl % 3) -= h;
          ReturnType tp{}, tm{};
          const Mat3 taup =
              elastoplastic_kirchhoff(*c.model, kind, Fp, s.F_old, s.converged, updated, &tp);
          const Mat3 taum =
              elastoplastic_kirchhoff(*c.model, kind, Fm, s.F_old, s.converged, updated, &tm);
          ASSERT_EQ(tp, c.expected);
          ASSERT_EQ(tm, c.expected);
          fd.col(static_cast<Eigen::Index>(j)) = flatten(taup - taum) / (2.0 * h);
          exact.col(static_cast<Eigen::Index>(j)) = r.dtau_dF.col(kl);
        }
        const double err = test::relative_error(fd, exact, c.model->elastic_stiffness().norm());
        EXPECT_LT(err, 1e-6);
        worst = std::max(worst, err);
      }
      std::printf("[ fd ] %-6s strain, %-24s worst relative error %.1e\n", kind_name(kind),
                  layout.name, worst);
    }
}

TEST(PlasticityKinematics, StressOnlyEqualsResponseStress) {
  for (const ReturnCase& c : return_cases())
    for (const Kinematics kind : {Kinematics::FiniteStrain, Kinematics::SmallStrain}) {
      SCOPED_TRACE(c.name);
      const Step s = make_step(kind, c.trial, c.kappa, false, 0);
      PlasticHistory h1, h2;
      const StressTangent r =
          elastoplastic_response(*c.model, kind, s.F_new, s.F_old, s.converged, h1);
      const Mat3 tau = elastoplastic_kirchhoff(*c.model, kind, s.F_new, s.F_old, s.converged, h2);
      EXPECT_EQ(r.kirchhoff, tau);
      EXPECT_EQ(h1.elastic, h2.elastic);
      EXPECT_EQ(h1.kappa, h2.kappa);
    }
}

namespace {

/// Deformation gradients of the hyperelastic tests: distinct, double and triple stretches.
std::vector<Mat3> elastic_gradients() {
  Mat2 uniaxial = Mat2::Identity();
  uniaxial(0, 0) = 1.25;
  return {kR * Vec3(1.3, 0.8, 1.1).asDiagonal() * kQ,
          Mat3{{1.2, 0.3, -0.1}, {0.05, 0.9, 0.2}, {-0.15, 0.1, 1.05}},
          embedded<2>(rotation2(0.4) * uniaxial),
          embedded<2>(rotation2(0.7) * (1.2 * Mat2::Identity())),
          kR * Vec3(1.2, 1.2, 0.9).asDiagonal() * kQ,
          kR * Vec3(1.2, 1.2 * (1.0 + 1e-9), 0.9).asDiagonal() * kQ,
          Mat3::Identity(),
          kR * (1.15 * Mat3::Identity())};
}

} // namespace

// An elastic first step (F_n = I, unstrained history) is the hyperelastic law itself: Hencky
// for finite strain, the small-strain LinearElastic law otherwise. Both go through the same
// eigen-decomposition (finite) or through the principal frame instead of index algebra (small),
// so they agree to round-off: 1e-12 relative.
TEST(PlasticityKinematics, ElasticStepEqualsHyperelasticLaw) {
  const VonMises never_yields(kSoilLame, 1e30);
  for (const Mat3& F : elastic_gradients()) {
    SCOPED_TRACE(::testing::Message() << F);
    for (const Kinematics kind : {Kinematics::FiniteStrain, Kinematics::SmallStrain}) {
      PlasticHistory updated;
      ReturnType type{};
      const StressTangent r = elastoplastic_response(never_yields, kind, F, Mat3::Identity(),
                                                     PlasticHistory::initial(kind), updated, &type);
      ASSERT_EQ(type, ReturnType::Elastic);
      const StressTangent ref = kind == Kinematics::FiniteStrain
                                    ? hencky_response(F, kSoilLame)
                                    : linear_elastic_response(F, kSoilLame);
      const double tau_scale = std::max(ref.kirchhoff.norm(), 1e-12 * kSoilLame.mu);
      EXPECT_LT((r.kirchhoff - ref.kirchhoff).norm(), 1e-12 * tau_scale);
      EXPECT_LT((r.dtau_dF - ref.dtau_dF).norm(), 1e-12 * ref.dtau_dF.norm());
    }
  }
}

// Superposing a rigid rotation Q on the whole motion (F_n, F and the spatial b_e,n) rotates tau;
// so does a rotation of F alone (a rigid spin within the step).
TEST(PlasticityKinematics, FiniteStrainIsObjective) {
  const Mat3 Q = rotation(2.3, Vec3(0.2, -1.0, 0.6));
  for (const ReturnCase& c : return_cases()) {
    SCOPED_TRACE(c.name);
    const Step s = make_step(Kinematics::FiniteStrain, c.trial, c.kappa, false, 0);
    PlasticHistory h, hq;
    const Mat3 tau = elastoplastic_kirchhoff(*c.model, Kinematics::FiniteStrain, s.F_new, s.F_old,
                                             s.converged, h);
    const double scale = tau.norm() + c.model->lame().mu * 1e-12;
    PlasticHistory rotated = s.converged;
    rotated.elastic = Q * s.converged.elastic * Q.transpose();
    const Mat3 tau_q = elastoplastic_kirchhoff(*c.model, Kinematics::FiniteStrain, Q * s.F_new,
                                               Q * s.F_old, rotated, hq);
    EXPECT_LT((tau_q - Q * tau * Q.transpose()).norm(), 1e-11 * scale);
    EXPECT_LT((hq.elastic - Q * h.elastic * Q.transpose()).norm(), 1e-11);
    EXPECT_NEAR(hq.kappa, h.kappa, 1e-12);
    const Mat3 tau_spin = elastoplastic_kirchhoff(*c.model, Kinematics::FiniteStrain, Q * s.F_new,
                                                  s.F_old, s.converged, hq);
    EXPECT_LT((tau_spin - Q * tau * Q.transpose()).norm(), 1e-11 * scale);
  }
}

// The stored state carries the stress: tau from b_e (Hencky on ln(b_e)/2) or sigma from eps_e,
// and a step with no further deformation from it returns the same stress and kappa.
TEST(PlasticityKinematics, StoredHistoryReproducesTheStress) {
  for (const ReturnCase& c : return_cases())
    for (const Kinematics kind : {Kinematics::FiniteStrain, Kinematics::SmallStrain}) {
      SCOPED_TRACE(::testing::Message() << kind_name(kind) << ": " << c.name);
      const Step s = make_step(kind, c.trial, c.kappa, false, 0);
      PlasticHistory h;
      const Mat3 tau = elastoplastic_kirchhoff(*c.model, kind, s.F_new, s.F_old, s.converged, h);
      const double scale = tau.norm() + 2e4;
      const LameParameters& l = c.model->lame();
      Mat3 from_history;
      if (kind == Kinematics::FiniteStrain) {
        const SpectralDecomposition d = spectral_decomposition(h.elastic);
        const Vec3 e = 0.5 * d.values.array().log().matrix();
        from_history = from_principal(d, Vec3::Constant(l.lambda * e.sum()) + 2.0 * l.mu * e);
      } else {
        from_history = (l.lambda * h.elastic.trace() * Mat3::Identity() + 2.0 * l.mu * h.elastic) *
                       s.F_new.transpose();
      }
      EXPECT_LT((from_history - tau).norm(), 1e-10 * scale);
      PlasticHistory again;
      const Mat3 tau_again = elastoplastic_kirchhoff(*c.model, kind, s.F_new, s.F_new, h, again);
      EXPECT_LT((tau_again - tau).norm(), 1e-10 * scale);
      EXPECT_NEAR(again.kappa, h.kappa, 1e-12);
    }
}

TEST(PlasticityKinematics, PlaneStrainHasNoOutOfPlaneShear) {
  for (const ReturnCase& c : return_cases())
    for (const Kinematics kind : {Kinematics::FiniteStrain, Kinematics::SmallStrain}) {
      SCOPED_TRACE(c.name);
      const Step s = make_step(kind, c.trial, c.kappa, true, 2);
      PlasticHistory h;
      const Mat3 tau = elastoplastic_kirchhoff(*c.model, kind, s.F_new, s.F_old, s.converged, h);
      const double scale = tau.norm();
      EXPECT_LT(std::abs(tau(0, 2)) + std::abs(tau(1, 2)), 1e-12 * scale);
      EXPECT_LT(std::abs(h.elastic(0, 2)) + std::abs(h.elastic(1, 2)), 1e-12);
    }
}

TEST(PlasticityKinematics, FailuresThrowNumericalError) {
  const MohrCoulomb m(kSoilLame, test::mc(2e4, 30.0, 10.0));
  const Mat3 inverted = Vec3(1.0, 1.0, -1.0).asDiagonal();
  PlasticHistory h;
  for (const Kinematics kind : {Kinematics::FiniteStrain, Kinematics::SmallStrain})
    EXPECT_THROW(elastoplastic_response(m, kind, inverted, Mat3::Identity(),
                                        PlasticHistory::initial(kind), h),
                 NumericalError);
  EXPECT_THROW(elastoplastic_response(m, Kinematics::FiniteStrain, Mat3::Identity(), inverted,
                                      PlasticHistory::initial(Kinematics::FiniteStrain), h),
               NumericalError);
  // a finite-strain history left at its default (b_e = 0, never initialised)
  EXPECT_THROW(elastoplastic_response(m, Kinematics::FiniteStrain, Mat3::Identity(),
                                      Mat3::Identity(), PlasticHistory{}, h),
               NumericalError);
}
