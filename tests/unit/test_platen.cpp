// A platen face (boundaries: platen): a rigid, frictionless plate whose nodes share one normal
// displacement, pushed by the loads on them.
#include "../../src/solver/shared_unknowns.hpp"
#include "implicit_test_support.hpp"

#include "talus/scene/scene.hpp"

#include <Eigen/Dense>

namespace {

using namespace talus::implicit_test;

// Two columns side by side, a stiff one (E1, 1 m wide) and a soft one (E2, 3 m wide), H = 2 m,
// nu = 0, between rollers; the grid's top is a platen and only the soft column is loaded, by
// q = 1 kPa. The platen squeezes both by the same strain, eps = q w2 / (E1 w1 + E2 w2): each
// column in uniaxial strain, sigma_yy = E eps, with no shear between them.
const std::string kColumns = R"(name: columns
analysis: implicit_quasistatic
grid: {origin: [0, 0], extent: [4, 2], cell_size: 0.25}
materials:
  - {name: stiff, model: linear_elastic, density: 2000, youngs_modulus: 4.0e7, poisson_ratio: 0}
  - {name: soft, model: linear_elastic, density: 2000, youngs_modulus: 1.0e7, poisson_ratio: 0}
bodies:
  - {name: stiff, material: stiff, shape: rectangle, min: [0, 0], max: [1, 2]}
  - {name: soft, material: soft, shape: rectangle, min: [1, 0], max: [4, 2]}
tractions:
  - {body: soft, side: top, traction: [0, -1.0e3]}
boundaries: {x_min: roller, x_max: roller, y_min: roller, y_max: platen}
time: {end_time: 1, dt: 1}
output: {every_steps: 1, fields: [reference_position, stress]}
solver: {shape: linear}
)";

constexpr double kStrain = -1.0e3 * 3 / (4.0e7 * 1 + 1.0e7 * 3);

/// Per point of the last frame: (y - Y) / Y.
std::vector<double> vertical_strains(const ResultsReader& r) {
  Index rows = 0, cols = 0;
  const Index last = r.frame_count() - 1;
  const auto x = r.read(last, "position", &rows, &cols);
  const auto x0 = r.read(last, "reference_position", &rows, &cols);
  std::vector<double> strain;
  for (Index p = 0; p < rows; ++p) {
    const auto y = static_cast<std::size_t>(2 * p + 1);
    strain.push_back((x[y] - x0[y]) / x0[y]);
  }
  return strain;
}

// The reduction against dense algebra: five unknowns, 1 and 3 tied into one group, 2 and 4 into
// another; T^T K T, T^T r and T x_r as matrices.
TEST(SharedUnknowns, ReducesAsTheDenseTransformation) {
  talus::SharedUnknowns shared;
  shared.reset(5);
  shared.share(1, 7);
  shared.share(3, 7);
  shared.share(2, 4);
  shared.share(4, 4);
  EXPECT_TRUE(shared.finish());
  EXPECT_FALSE(shared.finish()); // the same numbering again
  ASSERT_EQ(shared.size(), 3);
  Eigen::MatrixXd T = Eigen::MatrixXd::Zero(5, 3); // reduced: 0 -> {0}, 1 -> {1, 3}, 2 -> {2, 4}
  for (const auto& [row, col] :
       std::vector<std::pair<int, int>>{{0, 0}, {1, 1}, {3, 1}, {2, 2}, {4, 2}})
    T(row, col) = 1;
  const Eigen::MatrixXd K = Eigen::MatrixXd::Random(5, 5);
  const talus::SparseMatrix Ks = K.sparseView();
  EXPECT_LT((Eigen::MatrixXd(shared.condense(Ks)) - T.transpose() * K * T).norm(), 1e-14);
  const Eigen::VectorXd r = Eigen::VectorXd::Random(5);
  Eigen::VectorXd r_r = r;
  shared.condense(r_r);
  EXPECT_LT((r_r - T.transpose() * r).norm(), 1e-14);
  const Eigen::VectorXd x_r = Eigen::VectorXd::Random(3);
  EXPECT_EQ((shared.expand(x_r) - T * x_r).norm(), 0.0);
  EXPECT_EQ(shared.first_of(1), 1);
  EXPECT_EQ(shared.first_of(2), 2);
}

TEST_F(Implicit, PlatenSqueezesSideBySideColumnsByOneStrain) {
  const talus::RunResult r = run(kColumns, {}, "platen");
  ASSERT_EQ(r.status, "completed") << r.message;
  const std::vector<double> strain = vertical_strains(ResultsReader(root_ / "platen" / "run.h5"));
  ASSERT_FALSE(strain.empty());
  // Linear elasticity at a strain of 4e-5: the finite-strain terms are of that order relative.
  for (const double e : strain)
    EXPECT_NEAR(e / kStrain, 1.0, 2e-4);
}

// Without the platen the loaded soft column sinks alone (the check above can fail): its top
// settles several times the platen's, the stiff one's far less.
TEST_F(Implicit, PlatenFreeTopLetsTheLoadedColumnSinkAlone) {
  const talus::RunResult r =
      run(kColumns, {"boundaries={x_min: roller, x_max: roller, y_min: roller}"}, "free");
  ASSERT_EQ(r.status, "completed") << r.message;
  const std::vector<double> strain = vertical_strains(ResultsReader(root_ / "free" / "run.h5"));
  const auto [lo, hi] = std::minmax_element(strain.begin(), strain.end());
  EXPECT_GT(*lo / kStrain, 1.5);
  EXPECT_LT(*hi / kStrain, 0.5);
}

// A platen beside a fixed face moves its corner node too: the columns squeezed between a fixed
// x_min and a roller x_max keep one strain in the loaded soft column's far part.
TEST_F(Implicit, PlatenWinsOverAFixedSideFaceAtItsCorner) {
  talus::CaseSpec spec =
      talus::read_case_text(kColumns, "case.yaml",
                            {"boundaries={x_min: fixed, x_max: roller, y_min: roller, "
                             "y_max: platen}"});
  const talus::Scene<2> scene = talus::build_scene<2>(spec);
  const std::array<Index, 2> corner{0, scene.grid.cells(1)};
  EXPECT_EQ(scene.face_conditions.held(corner), 1u); // x held by the fixed face, y free
  EXPECT_EQ(scene.face_conditions.platen(corner, 1), talus::kYMax);
  EXPECT_EQ(scene.face_conditions.reaction_faces(corner)[1], -1);
}

TEST_F(Implicit, PlatenIsRefusedForExplicit) {
  try {
    talus::read_case_text(kColumns, "case.yaml",
                          {"analysis=explicit", "time={end_time: 1, cfl: 0.5}"});
    FAIL() << "expected an InputError";
  } catch (const talus::InputError& e) {
    EXPECT_EQ(e.where().key_path, "boundaries.y_max");
    EXPECT_NE(std::string(e.what()).find("a platen needs an implicit analysis"), std::string::npos)
        << e.what();
  }
}

} // namespace
