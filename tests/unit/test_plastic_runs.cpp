// Elasto-plastic materials in whole runs: the plastic_strain output field, the geostatic initial
// stress, the global Newton iteration with Mohr-Coulomb, and the colliding Tresca discs. Every
// run goes to a fresh temporary directory that is removed afterwards.
#include "talus/io/case_reader.hpp"
#include "talus/io/csv.hpp"
#include "talus/io/results.hpp"
#include "talus/material/plastic_material.hpp"
#include "talus/scene/scene.hpp"
#include "talus/solver/implicit_solver.hpp"
#include "talus/solver/run.hpp"
#include "temporary_directory.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using talus::Index;
using talus::ResultsReader;

namespace {

// A smooth rigid strip footing pushed into Mohr-Coulomb soil (half model, symmetry at x = 0):
// soil 2 m wide and 1 m deep (c = 5 kPa, phi = 30 deg, psi = 0, E = 10 MPa, nu = 0.3) starting
// from its geostatic K0 stress, under a stiff elastic footing 0.25 m wide (half of B = 0.5 m)
// whose top nodes are pushed down 20 mm. Elastic settlement reaches the Prandtl-type limit
// pressure (~ c Nc, Nc(30 deg) = 30, i.e. ~150 kPa) at s ~ q B (1 - nu^2) / E ~ 7 mm, so the
// soil under the footing's edge yields well before the end.
const std::string kFooting = R"(name: mc_footing
analysis: implicit_quasistatic
grid:
  origin: [0, 0]
  extent: [2, 1.5]
  cell_size: 0.125
materials:
  - {name: soil, model: mohr_coulomb, density: 2000, youngs_modulus: 1.0e7, poisson_ratio: 0.3,
     cohesion: 5.0e3, friction_angle: 30, dilation_angle: 0}
  - {name: footing, model: linear_elastic, density: 2000, youngs_modulus: 1.0e9,
     poisson_ratio: 0.2}
bodies:
  - {name: soil, material: soil, shape: rectangle, min: [0, 0], max: [2, 1],
     initial_stress: {type: geostatic}}
  - {name: footing, material: footing, shape: rectangle, min: [0, 1], max: [0.25, 1.125]}
gravity: [0, -9.81]
boundaries: {x_min: roller, x_max: roller, y_min: fixed}
prescribed:
  - {name: footing, min: [0, 1.125], max: [0.25, 1.125], displacement: [~, -0.02]}
time: {end_time: 1, dt: 0.125}
output: {every_steps: 1}
)";

std::string read_text(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// A fresh temporary directory per test, removed at the end.
class PlasticRuns : public talus::test_support::TemporaryDirectoryTest {
protected:
  /// Reads `text` with `overrides` and runs it in-process into root/<dir>.
  talus::RunResult run(const std::string& text, const std::vector<std::string>& overrides,
                       const std::string& dir) {
    const talus::CaseSpec spec = talus::read_case_text(text, "case.yaml", overrides);
    talus::RunOptions options;
    options.out_dir = root_ / dir;
    options.progress = false;
    return talus::run_case(spec, options);
  }
};

} // namespace

// -------------------------------------------------------------------------------------------------

// plastic_strain (on by default with a plastic material) is kappa >= 0 everywhere, exactly 0
// for the elastic footing's points and at t = 0, and the soil under the footing has yielded.
TEST_F(PlasticRuns, PlasticStrainFieldIsWrittenNonNegativeAndZeroForElasticPoints) {
  const talus::RunResult r = run(kFooting, {}, "footing");
  ASSERT_EQ(r.status, "completed") << r.message;
  ResultsReader results(r.out_dir / "run.h5");
  Index rows = 0, cols = 0;
  const auto first = results.read(0, "plastic_strain", &rows, &cols);
  EXPECT_EQ(*std::max_element(first.begin(), first.end()), 0.0);
  const Index last = results.frame_count() - 1;
  const auto kappa = results.read(last, "plastic_strain", &rows, &cols);
  const auto material = results.read(last, "material", &rows, &cols);
  double soil_max = 0;
  for (std::size_t p = 0; p < kappa.size(); ++p) {
    EXPECT_GE(kappa[p], 0.0) << "point " << p;
    if (material[p] == 1) // footing: linear_elastic
      EXPECT_EQ(kappa[p], 0.0) << "elastic point " << p;
    else
      soil_max = std::max(soil_max, kappa[p]);
  }
  EXPECT_GT(soil_max, 0.0) << "no soil point yielded";
}

// An all-elastic case writes no plastic_strain dataset and no such XDMF attribute.
TEST_F(PlasticRuns, ElasticRunHasNoPlasticStrainField) {
  const talus::RunResult r =
      run(kFooting,
          {"materials.soil={name: soil, model: linear_elastic, density: 2000, "
           "youngs_modulus: 1.0e7, poisson_ratio: 0.3}",
           "bodies.soil.initial_stress=~", "time.dt=1", "prescribed.0.displacement=[~, -1e-3]"},
          "elastic");
  ASSERT_EQ(r.status, "completed") << r.message;
  ResultsReader results(r.out_dir / "run.h5");
  for (Index k = 0; k < results.frame_count(); ++k) {
    const auto names = results.frame_fields(k);
    EXPECT_EQ(std::find(names.begin(), names.end(), "plastic_strain"), names.end());
  }
  EXPECT_EQ(read_text(r.out_dir / "run.xmf").find("plastic_strain"), std::string::npos);
}

// -------------------------------------------------------------------------------------------------

// The footing of kFooting without the footing body: the soil's surface nodes under the footing
// (half width 0.25 m) are pushed down 20 mm, their horizontal motion free (smooth, rigid). So
// the residual is scaled by the soil's own forces, not by a footing 100 times stiffer. The
// average pressure under the footing reaches ~240 kPa, beyond the ~150 kPa of c Nc: a plastic
// zone spreads under and around the footing.
const std::string kSoilFooting = R"(name: mc_soil_footing
analysis: implicit_quasistatic
grid:
  origin: [0, 0]
  extent: [2, 1.5]
  cell_size: 0.125
materials:
  - {name: soil, model: mohr_coulomb, density: 2000, youngs_modulus: 1.0e7, poisson_ratio: 0.3,
     cohesion: 5.0e3, friction_angle: 30, dilation_angle: 0}
bodies:
  - {name: soil, material: soil, shape: rectangle, min: [0, 0], max: [2, 1],
     initial_stress: {type: geostatic}}
gravity: [0, -9.81]
boundaries: {x_min: roller, x_max: roller, y_min: fixed}
prescribed:
  - {name: footing, min: [0, 1], max: [0.25, 1], displacement: [~, -0.02]}
time: {end_time: 1, dt: 0.125}
output: {every_steps: 1}
)";

// Newton with the consistent Mohr-Coulomb tangent on the footing (non-associated: psi = 0 <
// phi = 30 deg) converges quadratically: for consecutive iterates in the asymptotic range,
// r_{k+1} <= C r_k^2, with r = max|R| / force scale (the solver's measure, newton.log).
//
// The range: r_k <= 1e-3, past the first corrections in which many points still change between
// elastic and plastic or between plane and edge; and r_{k+1} >= 1e-11, 100 times the round-off
// floor of r: the stress carries round-off eps M (M ~ 1.3e7 Pa the constrained modulus), a
// nodal force eps M h ~ 4e-10 N, against a force scale of ~5e3 N (a footing node's share of
// the first increment's ~1.3e4 N reaction): ~1e-13.
// The constant: with the exact tangent, r_{k+1} / r_k^2 is a property of the problem (the
// curvature of R against |K^-1|), measured at most 49 here. C = 100 allows for that and still
// tells quadratic from linear convergence: a linear rate q gives r_{k+1} / r_k^2 = q / r_k >=
// 1000 q in the range, above 100 for any q >= 0.1, the order of the rates a continuum
// (non-consistent) tangent gives.
TEST_F(PlasticRuns, MohrCoulombFootingNewtonConvergesQuadratically) {
  const talus::CaseSpec spec = talus::read_case_text(kSoilFooting, "case.yaml", {});
  talus::Scene<2> scene = talus::build_scene<2>(spec);
  const auto solver = talus::make_implicit_solver(scene);
  // Non-associated flow: the automatic choice must be an LU backend, not Cholesky.
  EXPECT_EQ(solver->linear_solver(), "umfpack");
  const auto* soil = dynamic_cast<const talus::PlasticMaterial*>(scene.materials.at(0).get());
  ASSERT_NE(soil, nullptr);
  ASSERT_FALSE(soil->symmetric_tangent());

  constexpr int kSteps = 8;
  constexpr double kAsymptotic = 1e-3, kRoundOff = 1e-11, kQuadraticConstant = 100;
  double worst = 0;
  int pairs = 0;
  std::set<talus::ReturnType> returns;
  for (int k = 1; k <= kSteps; ++k) {
    SCOPED_TRACE("load step " + std::to_string(k));
    const double lambda = static_cast<double>(k) / kSteps;
    const talus::NewtonReport report = solver->step(lambda, lambda, spec.time.dt.value());
    ASSERT_TRUE(report.converged) << report.message;
    EXPECT_TRUE(report.abandoned_history.empty()) << "plain Newton failed, line search needed";
    const auto& r = report.residual_history;
    for (std::size_t i = 0; i + 1 < r.size(); ++i) {
      if (r[i] > kAsymptotic || r[i + 1] < kRoundOff)
        continue;
      ++pairs;
      worst = std::max(worst, r[i + 1] / (r[i] * r[i]));
      EXPECT_LE(r[i + 1], kQuadraticConstant * r[i] * r[i])
          << "r_k = " << r[i] << ", r_k+1 = " << r[i + 1];
    }
    for (const talus::Index p : scene.particles_of_material.at(0))
      returns.insert(soil->last_return(p));
  }
  std::cout << "pairs in the asymptotic range: " << pairs << ", largest r_k+1 / r_k^2 " << worst
            << "; returns:";
  for (const talus::ReturnType type : returns)
    std::cout << " " << talus::to_string(type) << ";";
  std::cout << "\n";
  EXPECT_GE(pairs, kSteps) << "too few iterates in the asymptotic range to judge the rate";
  EXPECT_TRUE(returns.count(talus::ReturnType::Surface));
  EXPECT_TRUE(returns.count(talus::ReturnType::CompressionEdge) ||
              returns.count(talus::ReturnType::ExtensionEdge) ||
              returns.count(talus::ReturnType::Apex))
      << "no point returned to an edge or the apex: the corners' tangents were not exercised";
}

// -------------------------------------------------------------------------------------------------

// A Mohr-Coulomb column 2 m high between rollers, fixed at the base, with geostatic initial
// stress. Frame 0 holds the initial stress itself: sigma_yy = -rho g (H - y), sigma_xx =
// sigma_zz = K0 sigma_yy, sigma_xy = 0, for a given K0 and for the default nu / (1 - nu); the
// formula is evaluated once per point, so the bound is round-off: 1e-12 rho g H.
//
// The stress is in equilibrium with gravity (d sigma_yy / dy = rho g), and with 2 x 2 points per
// cell the discrete internal force of this linear field matches the nodal weights, so the first
// implicit step under the full weight starts in equilibrium: its initial residual (newton.log,
// relative to a point's weight m g = 76.6 N) is round-off. The stress is stored as an elastic
// strain and recovered with an absolute error of ~eps M (M = lambda + 2 mu = 1.35e7 Pa), a
// nodal force of ~eps M h = 3.7e-10 N, 4.8e-12 m g; bound ten times that, 4.8e-11.
// So the column does not move: compared with the elastic settlement of the same column loaded
// from zero stress, rho g H^2 / (2 M) = 2.9 mm at the top, an imbalance of r point weights
// moves it by at most ~r x (32 points per column) x the settlement, 1.5e-9 of it; bound 1e-8.
TEST_F(PlasticRuns, GeostaticInitialStressIsK0AndInEquilibrium) {
  const std::string column = R"(name: column
analysis: implicit_quasistatic
grid: {origin: [0, 0], extent: [1, 2.5], cell_size: 0.125}
materials:
  - {name: soil, model: mohr_coulomb, density: 2000, youngs_modulus: 1.0e7, poisson_ratio: 0.3,
     cohesion: 5.0e3, friction_angle: 30}
bodies:
  - {name: soil, material: soil, shape: rectangle, min: [0, 0], max: [1, 2],
     initial_stress: {type: geostatic, k0: 0.6}}
gravity: [0, -9.81]
boundaries: {x_min: roller, x_max: roller, y_min: fixed}
time: {end_time: 1, dt: 1}
output: {every_steps: 1}
)";
  constexpr double kRhoG = 2000 * 9.81, kHeight = 2.0, kNu = 0.3;
  // Largest displacement of any point between the first and the last frame.
  auto largest_displacement = [](const ResultsReader& results) {
    Index rows = 0, cols = 0;
    const auto x0 = results.read(0, "position", &rows, &cols);
    const auto x1 = results.read(results.frame_count() - 1, "position", &rows, &cols);
    double largest = 0;
    for (std::size_t i = 0; i + 1 < x0.size(); i += 2)
      largest = std::max(largest, std::hypot(x1[i] - x0[i], x1[i + 1] - x0[i + 1]));
    return largest;
  };

  const talus::RunResult plain = run(column, {"bodies.soil.initial_stress=~"}, "plain");
  ASSERT_EQ(plain.status, "completed") << plain.message;
  const double settlement = largest_displacement(ResultsReader(plain.out_dir / "run.h5"));
  const double E = 1.0e7, M = E * (1 - kNu) / ((1 + kNu) * (1 - 2 * kNu));
  EXPECT_NEAR(settlement, kRhoG * kHeight * kHeight / (2 * M), 0.05 * settlement)
      << "the reference settlement is not the elastic column's";

  const std::vector<std::pair<std::string, double>> variants = {
      {"bodies.soil.initial_stress={type: geostatic, k0: 0.6}", 0.6},
      {"bodies.soil.initial_stress={type: geostatic}", kNu / (1 - kNu)}};
  for (const auto& [initial_stress, k0] : variants) {
    SCOPED_TRACE(initial_stress);
    const talus::RunResult r = run(column, {initial_stress}, "k0_" + std::to_string(k0));
    ASSERT_EQ(r.status, "completed") << r.message;
    ResultsReader results(r.out_dir / "run.h5");
    Index rows = 0, cols = 0;
    const auto x0 = results.read(0, "position", &rows, &cols);
    const auto stress = results.read(0, "stress", &rows, &cols);
    ASSERT_EQ(cols, 6); // xx, xy, xz, yy, yz, zz
    const double bound = 1e-12 * kRhoG * kHeight;
    for (Index p = 0; p < rows; ++p) {
      const auto s = static_cast<std::size_t>(6 * p);
      const double syy = -kRhoG * (kHeight - x0[static_cast<std::size_t>(2 * p + 1)]);
      EXPECT_NEAR(stress[s + 3], syy, bound) << "point " << p;
      EXPECT_NEAR(stress[s + 0], k0 * syy, bound) << "point " << p;
      EXPECT_NEAR(stress[s + 5], k0 * syy, bound) << "point " << p;
      EXPECT_EQ(stress[s + 1], 0.0) << "point " << p;
    }
    std::ifstream log(r.out_dir / "newton.log");
    std::string line;
    while (std::getline(log, line) && line.front() == '#') {
    }
    ASSERT_NE(line.find('|'), std::string::npos) << line;
    const double initial_residual = std::stod(line.substr(line.find('|') + 1));
    const double eps = std::numeric_limits<double>::epsilon();
    EXPECT_LE(initial_residual, 10 * eps * M * 0.125 / (kRhoG * 0.0625 * 0.0625));
    const double moved = largest_displacement(results);
    std::cout << "K0 = " << k0 << ": largest displacement " << moved
              << " m, elastic settlement from zero stress " << settlement << " m, ratio "
              << moved / settlement << ", initial residual " << initial_residual << "\n";
    EXPECT_LE(moved, 1e-8 * settlement);
  }
}

// -------------------------------------------------------------------------------------------------

namespace {

/// Distance between the two disc centres (the probes lower_centre and upper_centre) at time t,
/// interpolated linearly between the rows of timeseries.csv.
double centre_distance(const talus::CsvTable& series, double t) {
  const auto& time = series.column("time");
  auto distance = [&](std::size_t i) {
    return std::hypot(series.column("upper_centre.x")[i] - series.column("lower_centre.x")[i],
                      series.column("upper_centre.y")[i] - series.column("lower_centre.y")[i]);
  };
  for (std::size_t i = 0; i + 1 < time.size(); ++i)
    if (time[i] <= t && t <= time[i + 1])
      return distance(i) +
             (distance(i + 1) - distance(i)) * (t - time[i]) / (time[i + 1] - time[i]);
  throw std::out_of_range("time " + std::to_string(t) + " outside the run");
}

/// What the colliding-discs test measures of one run.
struct DiscRun {
  double momentum_error = 0; ///< max_t |P(t)| / sum m |v0|
  double momentum_bound = 0; ///< 10 x steps x machine epsilon
  double energy_loss = 0;    ///< (E(0) - E(end)) / E(0), kinetic + stored
  double closing_speed = 0;  ///< mean approach speed of the centres over the contact phase
};

} // namespace

// The talk's colliding discs with Tresca discs (c = 5 Pa; cases/colliding_discs_tresca.yaml and
// its implicit-dynamic twin), against the same discs with Hencky elasticity alone (the Tresca
// model's elastic law). Run to t = 0.05, past first contact (~0.03) and the elastic discs'
// rebound, at the cases' cell size h = 0.025 and at 2h.
//  * Momentum: no external force, so |P(t)| stays at round-off in both solvers (explicit: sum
//    of the P2G/G2P transfers; implicit: Newton's update makes the residual's sum over the
//    nodes vanish to round-off, since internal and ghost-penalty forces sum to zero): bound
//    10 x steps x eps of sum m |v0|, as in the elastic verification case.
//  * Dissipation: the elastic discs only lose what the discretisation loses; plastic flow adds
//    its dissipation c |d eps^p|, so the Tresca discs lose more energy in either solver (same
//    resolution, same solver).
//  * Agreement: the solvers share the grid, points and shape functions and differ in time
//    integration (Newmark at dt = 7e-4, 2.3 times the explicit limit, against explicit steps
//    at Courant number 0.5) and in the particle-grid transfer, so their gap is a discretisation
//    error and must shrink under refinement: the mean closing speed of the disc centres over
//    the contact phase (t = 0.03 to 0.05) must differ less at h than at 2h, and by at most 2 %
//    at h (the Tresca discs flow, so their deformation varies with the resolution; measured
//    0.03 % at h and 3.2 % at 2h). Measured energy losses at 2h: explicit 1.43 % (Tresca) vs
//    1.21 % (elastic), implicit 23.8 % vs 8.9 %.
TEST_F(PlasticRuns, CollidingTrescaDiscsConserveMomentumDissipateAndAgree) {
  const fs::path cases = fs::path(TALUS_TESTS_DIR).parent_path() / "cases";
  const std::string hencky = "materials.disc={name: disc, model: hencky, density: 20, "
                             "youngs_modulus: 1.0e5, poisson_ratio: 0.3}";
  constexpr double kContact = 0.03, kEnd = 0.05;
  auto run_discs = [&](const std::string& file, const std::vector<std::string>& extra,
                       const std::string& dir) {
    std::vector<std::string> overrides = {"time.end_time=" + std::to_string(kEnd),
                                          "output.voxels=false", "output.every_time=0.01"};
    overrides.insert(overrides.end(), extra.begin(), extra.end());
    const talus::CaseSpec spec = talus::read_case_file((cases / file).string(), overrides);
    talus::RunOptions options;
    options.out_dir = root_ / dir;
    options.progress = false;
    const talus::RunResult r = talus::run_case(spec, options);
    EXPECT_EQ(r.status, "completed") << dir << ": " << r.message;
    const talus::CsvTable series = talus::read_csv(r.out_dir / "timeseries.csv");
    ResultsReader results(r.out_dir / "run.h5");
    Index rows = 0, cols = 0;
    const auto mass = results.read(0, "mass", &rows, &cols);
    const auto v0 = results.read(0, "velocity", &rows, &cols);
    double momentum_scale = 0;
    for (std::size_t p = 0; p < mass.size(); ++p)
      momentum_scale += mass[p] * std::hypot(v0[2 * p], v0[2 * p + 1]);
    DiscRun d;
    for (std::size_t i = 0; i < series.rows(); ++i)
      d.momentum_error = std::max(d.momentum_error, std::hypot(series.column("momentum_x")[i],
                                                               series.column("momentum_y")[i]) /
                                                        momentum_scale);
    d.momentum_bound = 10.0 * static_cast<double>(r.steps) * std::numeric_limits<double>::epsilon();
    const auto& total = series.column("total_energy");
    d.energy_loss = (total.front() - total.back()) / total.front();
    d.closing_speed =
        (centre_distance(series, kContact) - centre_distance(series, kEnd)) / (kEnd - kContact);
    std::cout << dir << ": steps " << r.steps << ", |P| / sum m|v0| " << d.momentum_error
              << ", energy loss " << d.energy_loss << ", closing speed " << d.closing_speed << "\n";
    return d;
  };
  const std::string explicit_case = "colliding_discs_tresca.yaml";
  const std::string implicit_case = "colliding_discs_tresca_implicit.yaml";
  double gap_coarse = 0;
  for (const double h : {0.05, 0.025}) {
    SCOPED_TRACE("h = " + std::to_string(h));
    const std::string cell = "grid.cell_size=" + std::to_string(h);
    const std::string tag = h > 0.03 ? "_2h" : "_h";
    const DiscRun tresca_explicit = run_discs(explicit_case, {cell}, "tresca_explicit" + tag);
    const DiscRun tresca_implicit = run_discs(implicit_case, {cell}, "tresca_implicit" + tag);
    for (const DiscRun& d : {tresca_explicit, tresca_implicit})
      EXPECT_LE(d.momentum_error, d.momentum_bound);
    const double gap = std::abs(tresca_implicit.closing_speed - tresca_explicit.closing_speed) /
                       tresca_explicit.closing_speed;
    std::cout << "closing speeds differ by " << gap << "\n";
    if (h > 0.03) {
      gap_coarse = gap;
      // The energy comparison at the coarser grid only: the argument holds at any resolution.
      const DiscRun elastic_explicit =
          run_discs(explicit_case, {cell, hencky}, "elastic_explicit" + tag);
      const DiscRun elastic_implicit =
          run_discs(implicit_case, {cell, hencky}, "elastic_implicit" + tag);
      for (const DiscRun& d : {elastic_explicit, elastic_implicit})
        EXPECT_LE(d.momentum_error, d.momentum_bound);
      EXPECT_GT(tresca_explicit.energy_loss, elastic_explicit.energy_loss);
      EXPECT_GT(tresca_implicit.energy_loss, elastic_implicit.energy_loss);
    } else {
      EXPECT_LT(gap, gap_coarse);
      EXPECT_LE(gap, 0.02);
    }
  }
}
