// Cost of one finite-strain elasto-plastic material-point update with its consistent tangent
// (elastoplastic_response: trial b_e, eigen-decomposition, principal return, 9x9 dtau/dF), per
// model and per return type: BM_FiniteStrainUpdate/<model>/<return>. The time per iteration is
// the time per call. Each input is chosen to hit the named return, checked before timing;
// hencky_response (the elastic law alone) is the baseline.
#include "talus/material/hyperelastic.hpp"
#include "talus/material/plasticity/drucker_prager.hpp"
#include "talus/material/plasticity/elastoplastic_response.hpp"
#include "talus/material/plasticity/mohr_coulomb.hpp"
#include "talus/material/plasticity/tresca.hpp"
#include "talus/material/plasticity/von_mises.hpp"

#include <benchmark/benchmark.h>

namespace {

using namespace talus;

const LameParameters kLame = LameParameters::from_young_poisson(2.0e7, 0.3);

/// Principal strain: volumetric ev, deviatoric length rho between triaxial extension (t = 0)
/// and compression (t = 1).
Vec3 strain(double ev, double rho, double t) {
  const Vec3 d = (1.0 - t) * Vec3(2.0, -1.0, -1.0) + t * Vec3(1.0, 1.0, -2.0);
  return Vec3::Constant(ev / 3.0) + rho * d.normalized();
}

/// F with b = F F^T = R exp(2 eps) R^T (F_n = I, unstrained history): the trial strain is eps.
Mat3 gradient(const Vec3& eps) {
  const Mat3 R = Eigen::AngleAxisd(0.7, Vec3(1.0, 2.0, -0.5).normalized()).toRotationMatrix();
  return R * eps.array().exp().matrix().asDiagonal();
}

const VonMises& von_mises() {
  static const VonMises m(kLame, 4.0e4, 2.0e6);
  return m;
}
const Tresca& tresca() {
  static const Tresca m(kLame, 2.0e4);
  return m;
}
const MohrCoulomb& mohr_coulomb() {
  static const MohrCoulomb m(kLame, FrictionalStrengthParameters{2.0e4, 30.0, 10.0, {}});
  return m;
}
const MohrCoulomb& mohr_coulomb_softening() {
  static const MohrCoulomb m(
      kLame, FrictionalStrengthParameters{2.0e4, 35.0, 5.0, ResidualStrength{5.0e3, 25.0, 0.02}});
  return m;
}
const DruckerPrager& drucker_prager() {
  static const DruckerPrager m(kLame, FrictionalStrengthParameters{2.0e4, 30.0, 10.0, {}});
  return m;
}
const DruckerPrager& drucker_prager_softening() {
  static const DruckerPrager m(
      kLame, FrictionalStrengthParameters{2.0e4, 35.0, 5.0, ResidualStrength{5.0e3, 25.0, 0.02}});
  return m;
}

void BM_FiniteStrainUpdate(benchmark::State& state, const PlasticModel& model, Vec3 eps,
                           double kappa, ReturnType expected) {
  const Mat3 F = gradient(eps);
  const Mat3 F_old = Mat3::Identity();
  PlasticHistory converged = PlasticHistory::initial(Kinematics::FiniteStrain);
  converged.kappa = kappa;
  PlasticHistory updated;
  ReturnType type{};
  elastoplastic_response(model, Kinematics::FiniteStrain, F, F_old, converged, updated, &type);
  if (type != expected) {
    state.SkipWithError("input does not hit the intended return type");
    return;
  }
  for (auto _ : state) {
    benchmark::DoNotOptimize(
        elastoplastic_response(model, Kinematics::FiniteStrain, F, F_old, converged, updated));
    benchmark::ClobberMemory();
  }
}

void hencky_baseline(benchmark::State& state) {
  const Mat3 F = gradient(strain(-3e-3, 1e-2, 0.3));
  for (auto _ : state)
    benchmark::DoNotOptimize(hencky_response(F, kLame));
}

using RT = ReturnType;

} // namespace

BENCHMARK(hencky_baseline)->Name("BM_FiniteStrainUpdate/hencky_elastic_law_baseline");
BENCHMARK_CAPTURE(BM_FiniteStrainUpdate, von_mises / elastic, von_mises(), strain(-2e-3, 1e-3, 0.3),
                  0.0, RT::Elastic);
BENCHMARK_CAPTURE(BM_FiniteStrainUpdate, von_mises / surface, von_mises(), strain(-2e-3, 1e-2, 0.3),
                  0.0, RT::Surface);
BENCHMARK_CAPTURE(BM_FiniteStrainUpdate, tresca / elastic, tresca(), strain(-3e-3, 1e-3, 0.5), 0.0,
                  RT::Elastic);
BENCHMARK_CAPTURE(BM_FiniteStrainUpdate, tresca / plane, tresca(), strain(-3e-3, 1e-2, 0.5), 0.0,
                  RT::Surface);
BENCHMARK_CAPTURE(BM_FiniteStrainUpdate, tresca / compression_edge, tresca(),
                  strain(-3e-3, 1e-2, 0.9), 0.0, RT::CompressionEdge);
BENCHMARK_CAPTURE(BM_FiniteStrainUpdate, tresca / extension_edge, tresca(),
                  strain(-3e-3, 1e-2, 0.1), 0.0, RT::ExtensionEdge);
BENCHMARK_CAPTURE(BM_FiniteStrainUpdate, mohr_coulomb / elastic, mohr_coulomb(),
                  strain(-3e-3, 3e-3, 0.5), 0.0, RT::Elastic);
BENCHMARK_CAPTURE(BM_FiniteStrainUpdate, mohr_coulomb / plane, mohr_coulomb(),
                  strain(-3e-3, 6e-3, 0.5), 0.0, RT::Surface);
BENCHMARK_CAPTURE(BM_FiniteStrainUpdate, mohr_coulomb / compression_edge, mohr_coulomb(),
                  strain(0.0, 1e-2, 0.9), 0.0, RT::CompressionEdge);
BENCHMARK_CAPTURE(BM_FiniteStrainUpdate, mohr_coulomb / extension_edge, mohr_coulomb(),
                  strain(0.0, 1e-2, 0.1), 0.0, RT::ExtensionEdge);
BENCHMARK_CAPTURE(BM_FiniteStrainUpdate, mohr_coulomb / apex, mohr_coulomb(),
                  strain(1.2e-2, 3e-3, 0.3), 0.0, RT::Apex);
BENCHMARK_CAPTURE(BM_FiniteStrainUpdate, mohr_coulomb_softening / plane, mohr_coulomb_softening(),
                  strain(-3e-3, 8e-3, 0.5), 0.005, RT::Surface);
BENCHMARK_CAPTURE(BM_FiniteStrainUpdate, mohr_coulomb_softening / compression_edge,
                  mohr_coulomb_softening(), strain(0.0, 1e-2, 0.9), 0.005, RT::CompressionEdge);
BENCHMARK_CAPTURE(BM_FiniteStrainUpdate, mohr_coulomb_softening / extension_edge,
                  mohr_coulomb_softening(), strain(0.0, 1e-2, 0.1), 0.005, RT::ExtensionEdge);
BENCHMARK_CAPTURE(BM_FiniteStrainUpdate, mohr_coulomb_softening / apex, mohr_coulomb_softening(),
                  strain(1.2e-2, 3e-3, 0.3), 0.005, RT::Apex);
BENCHMARK_CAPTURE(BM_FiniteStrainUpdate, drucker_prager / elastic, drucker_prager(),
                  strain(-3e-3, 2e-3, 0.5), 0.0, RT::Elastic);
BENCHMARK_CAPTURE(BM_FiniteStrainUpdate, drucker_prager / cone, drucker_prager(),
                  strain(-3e-3, 1e-2, 0.3), 0.0, RT::Surface);
BENCHMARK_CAPTURE(BM_FiniteStrainUpdate, drucker_prager / apex, drucker_prager(),
                  strain(1.2e-2, 2e-3, 0.3), 0.0, RT::Apex);
BENCHMARK_CAPTURE(BM_FiniteStrainUpdate, drucker_prager_softening / cone,
                  drucker_prager_softening(), strain(-3e-3, 1e-2, 0.3), 0.005, RT::Surface);
BENCHMARK_CAPTURE(BM_FiniteStrainUpdate, drucker_prager_softening / apex,
                  drucker_prager_softening(), strain(1.2e-2, 2e-3, 0.3), 0.005, RT::Apex);
