// Cost of one elasto-plastic material-point update, per model, per return type and per
// kinematics; the time per iteration is the time per point:
//   BM_<Kinematics>Update/<model>/<return>   stress and 9x9 consistent tangent dtau/dF
//                                            (elastoplastic_response: what the implicit
//                                            solver evaluates per point and Newton iterate)
//   BM_<Kinematics>Stress/<model>/<return>   the Kirchhoff stress alone
//                                            (elastoplastic_kirchhoff: the explicit update)
// with <Kinematics> FiniteStrain (trial b_e, eigen-decomposition, principal return, exponential
// map) or SmallStrain (eps = sym(F) - I). Every model runs each of its return types: elastic,
// the smooth surface (plane, cylinder or cone), the compression and extension edges (Tresca,
// Mohr-Coulomb) and the apex (Mohr-Coulomb, Drucker-Prager); the softening variants return
// with kappa > 0. Each input is checked to hit the named return before timing. The elastic
// laws alone (hencky_response, linear_elastic_response) are the baselines.
// Run: build/bench/talus_bench --benchmark_filter='Update|Stress'.
#include "talus/material/hyperelastic.hpp"
#include "talus/material/plasticity/drucker_prager.hpp"
#include "talus/material/plasticity/elastoplastic_response.hpp"
#include "talus/material/plasticity/mohr_coulomb.hpp"
#include "talus/material/plasticity/tresca.hpp"
#include "talus/material/plasticity/von_mises.hpp"

#include <benchmark/benchmark.h>
#include <string>
#include <utility>

namespace {

using namespace talus;

const LameParameters kLame = LameParameters::from_young_poisson(2.0e7, 0.3);

/// Principal strain: volumetric ev, deviatoric length rho between triaxial extension (t = 0)
/// and compression (t = 1).
Vec3 strain(double ev, double rho, double t) {
  const Vec3 d = (1.0 - t) * Vec3(2.0, -1.0, -1.0) + t * Vec3(1.0, 1.0, -2.0);
  return Vec3::Constant(ev / 3.0) + rho * d.normalized();
}

/// A rotation that mixes all three axes, so no eigen-decomposition is trivially diagonal.
Mat3 rotation() {
  return Eigen::AngleAxisd(0.7, Vec3(1.0, 2.0, -0.5).normalized()).toRotationMatrix();
}

/// F whose trial strain from an unstrained history (F_n = I) has the principal values eps:
/// finite strain F = R exp(eps) (b = R exp(2 eps) R^T); small strain F = I + Q eps Q^T.
Mat3 gradient(Kinematics kind, const Vec3& eps) {
  const Mat3 R = rotation();
  if (kind == Kinematics::FiniteStrain)
    return R * eps.array().exp().matrix().asDiagonal();
  return Mat3::Identity() + R * eps.asDiagonal() * R.transpose();
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

/// One benchmarked point: a model, its trial strain, the converged kappa and the return the
/// input must take.
struct Point {
  const char* name; ///< "<model>/<return>"
  const PlasticModel& model;
  Vec3 eps;
  double kappa;
  ReturnType expected;
};

template <bool WithTangent>
void BM_Update(benchmark::State& state, const Point& point, Kinematics kind) {
  const Mat3 F = gradient(kind, point.eps);
  const Mat3 F_old = Mat3::Identity();
  PlasticHistory converged = PlasticHistory::initial(kind);
  converged.kappa = point.kappa;
  PlasticHistory updated;
  ReturnType type{};
  elastoplastic_response(point.model, kind, F, F_old, converged, updated, &type);
  if (type != point.expected) {
    state.SkipWithError("input does not hit the intended return type");
    return;
  }
  for (auto _ : state) {
    if constexpr (WithTangent)
      benchmark::DoNotOptimize(
          elastoplastic_response(point.model, kind, F, F_old, converged, updated));
    else
      benchmark::DoNotOptimize(
          elastoplastic_kirchhoff(point.model, kind, F, F_old, converged, updated));
    benchmark::ClobberMemory();
  }
}

void hencky_baseline(benchmark::State& state) {
  const Mat3 F = gradient(Kinematics::FiniteStrain, strain(-3e-3, 1e-2, 0.3));
  for (auto _ : state)
    benchmark::DoNotOptimize(hencky_response(F, kLame));
}

void linear_elastic_baseline(benchmark::State& state) {
  const Mat3 F = gradient(Kinematics::SmallStrain, strain(-3e-3, 1e-2, 0.3));
  for (auto _ : state)
    benchmark::DoNotOptimize(linear_elastic_response(F, kLame));
}

using RT = ReturnType;

// Strains are a few times the yield strain (c / G ~ 3e-3) for the plastic returns; the edges
// sit near the compression (t = 1) and extension (t = 0) meridians, the apex under hydrostatic
// tension. The same inputs hit the same returns in both kinematics (checked at run time).
const Point kPoints[] = {
    {"von_mises/elastic", von_mises(), strain(-2e-3, 1e-3, 0.3), 0.0, RT::Elastic},
    {"von_mises/surface", von_mises(), strain(-2e-3, 1e-2, 0.3), 0.0, RT::Surface},
    {"tresca/elastic", tresca(), strain(-3e-3, 1e-3, 0.5), 0.0, RT::Elastic},
    {"tresca/plane", tresca(), strain(-3e-3, 1e-2, 0.5), 0.0, RT::Surface},
    {"tresca/compression_edge", tresca(), strain(-3e-3, 1e-2, 0.9), 0.0, RT::CompressionEdge},
    {"tresca/extension_edge", tresca(), strain(-3e-3, 1e-2, 0.1), 0.0, RT::ExtensionEdge},
    {"mohr_coulomb/elastic", mohr_coulomb(), strain(-3e-3, 3e-3, 0.5), 0.0, RT::Elastic},
    {"mohr_coulomb/plane", mohr_coulomb(), strain(-3e-3, 6e-3, 0.5), 0.0, RT::Surface},
    {"mohr_coulomb/compression_edge", mohr_coulomb(), strain(0.0, 1e-2, 0.9), 0.0,
     RT::CompressionEdge},
    {"mohr_coulomb/extension_edge", mohr_coulomb(), strain(0.0, 1e-2, 0.1), 0.0, RT::ExtensionEdge},
    {"mohr_coulomb/apex", mohr_coulomb(), strain(1.2e-2, 3e-3, 0.3), 0.0, RT::Apex},
    {"mohr_coulomb_softening/plane", mohr_coulomb_softening(), strain(-3e-3, 8e-3, 0.5), 0.005,
     RT::Surface},
    {"mohr_coulomb_softening/compression_edge", mohr_coulomb_softening(), strain(0.0, 1e-2, 0.9),
     0.005, RT::CompressionEdge},
    {"mohr_coulomb_softening/extension_edge", mohr_coulomb_softening(), strain(0.0, 1e-2, 0.1),
     0.005, RT::ExtensionEdge},
    {"mohr_coulomb_softening/apex", mohr_coulomb_softening(), strain(1.2e-2, 3e-3, 0.3), 0.005,
     RT::Apex},
    {"drucker_prager/elastic", drucker_prager(), strain(-3e-3, 2e-3, 0.5), 0.0, RT::Elastic},
    {"drucker_prager/cone", drucker_prager(), strain(-3e-3, 1e-2, 0.3), 0.0, RT::Surface},
    {"drucker_prager/apex", drucker_prager(), strain(1.2e-2, 2e-3, 0.3), 0.0, RT::Apex},
    {"drucker_prager_softening/cone", drucker_prager_softening(), strain(-3e-3, 1e-2, 0.3), 0.005,
     RT::Surface},
    {"drucker_prager_softening/apex", drucker_prager_softening(), strain(1.2e-2, 2e-3, 0.3), 0.005,
     RT::Apex},
};

// Registers every point for both kinematics, with and without the tangent.
[[maybe_unused]] const bool kRegistered = [] {
  benchmark::RegisterBenchmark("BM_FiniteStrainUpdate/hencky_elastic_law_baseline",
                               hencky_baseline);
  benchmark::RegisterBenchmark("BM_SmallStrainUpdate/linear_elastic_law_baseline",
                               linear_elastic_baseline);
  for (const auto& [kind, label] : {std::pair{Kinematics::FiniteStrain, "FiniteStrain"},
                                    std::pair{Kinematics::SmallStrain, "SmallStrain"}})
    for (const Point& point : kPoints) {
      const std::string family = std::string("BM_") + label;
      benchmark::RegisterBenchmark((family + "Update/" + point.name).c_str(), BM_Update<true>,
                                   point, kind);
      benchmark::RegisterBenchmark((family + "Stress/" + point.name).c_str(), BM_Update<false>,
                                   point, kind);
    }
  return true;
}();

} // namespace
