// Elasto-plastic materials in whole runs: the plastic_strain output field, the geostatic initial
// stress, the global Newton iteration with Mohr-Coulomb, and the colliding Tresca discs. Every
// run goes to a fresh temporary directory that is removed afterwards.
#include "talus/io/case_reader.hpp"
#include "talus/io/csv.hpp"
#include "talus/io/results.hpp"
#include "talus/solver/run.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
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
class PlasticRuns : public ::testing::Test {
protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::random_device rd;
    for (int attempt = 0; attempt < 100 && root_.empty(); ++attempt) {
      const fs::path candidate =
          fs::temp_directory_path() / ("talus_plastic_" + std::string(info->name()) + "_" +
                                       std::to_string(::getpid()) + "_" + std::to_string(rd()));
      std::error_code ec;
      if (fs::create_directory(candidate, ec))
        root_ = candidate;
    }
    ASSERT_FALSE(root_.empty()) << "cannot create a temporary directory";
  }
  void TearDown() override {
    std::error_code ec;
    if (!root_.empty())
      fs::remove_all(root_, ec);
  }

  /// Reads `text` with `overrides` and runs it in-process into root/<dir>.
  talus::RunResult run(const std::string& text, const std::vector<std::string>& overrides,
                       const std::string& dir) {
    const talus::CaseSpec spec = talus::read_case_text(text, "case.yaml", overrides);
    talus::RunOptions options;
    options.out_dir = root_ / dir;
    options.progress = false;
    return talus::run_case(spec, options);
  }

  fs::path root_;
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
