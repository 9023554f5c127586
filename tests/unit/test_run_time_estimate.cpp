// The rough run time `talus check` prints (talus/scene/run_time_estimate.hpp): its model, not
// the clock. An explicit 2D step costs its points plus a fixed overhead; halving the cell size
// doubles the CFL-limited steps and quadruples the points, so a large body's estimate grows 8
// times and a small one's, whose steps cost their overhead, about 2 times.
#include "talus/io/case_reader.hpp"
#include "talus/scene/run_time_estimate.hpp"

#include <gtest/gtest.h>

#include <string>

namespace {

const std::string kDiscs = R"(name: block
analysis: explicit
grid: {origin: [0, 0], extent: [1, 1], cell_size: 0.05}
materials:
  - {name: soil, model: linear_elastic, density: 2000, youngs_modulus: 1.0e7, poisson_ratio: 0.3}
bodies:
  - {name: block, material: soil, shape: rectangle, min: [0.2, 0.2], max: [0.8, 0.8]}
time: {end_time: 0.01, cfl: 0.5}
)";

/// The estimate of kDiscs with the overrides, less the process's start.
talus::RunTimeEstimate estimate(const std::vector<std::string>& overrides, int threads = 2) {
  const talus::CaseSpec spec = talus::read_case_text(kDiscs, "case.yaml", overrides);
  talus::RunTimeEstimate e = talus::estimate_run_time(spec, talus::estimate_memory(spec), threads);
  EXPECT_GT(e.start_seconds, 0);
  e.seconds -= e.start_seconds;
  return e;
}

TEST(RunTimeEstimate, ExplicitCostIsPointsTimesCflSteps) {
  const auto coarse = estimate({});
  const auto fine = estimate({"grid.cell_size=0.025"});
  // c_p = sqrt((lambda + 2 mu) / rho) = 82.0 m/s; dt = 0.5 h / c_p = 3.05e-4 s: 33 steps.
  EXPECT_EQ(coarse.steps, 33);
  EXPECT_EQ(fine.steps, 66);
  EXPECT_EQ(coarse.unknowns, 0);
  // 576 points and 2304: the steps' overhead dominates.
  EXPECT_GT(fine.seconds / coarse.seconds, 2.0);
  EXPECT_LT(fine.seconds / coarse.seconds, 2.6);
  // 360 000 points and 1.44 million: the points dominate.
  const double large =
      estimate({"grid.cell_size=0.001"}).seconds / estimate({"grid.cell_size=0.002"}).seconds;
  EXPECT_GT(large, 7.5);
  EXPECT_LE(large, 8.0);
  // One thread is slower than two.
  EXPECT_GT(estimate({}, 1).seconds, coarse.seconds);
}

TEST(RunTimeEstimate, ImplicitCostFollowsLoadStepsAndUnknowns) {
  const std::vector<std::string> implicit = {"analysis=implicit_quasistatic",
                                             "time={end_time: 1, dt: 0.1}"};
  const auto ten = estimate(implicit);
  EXPECT_EQ(ten.steps, 10);
  EXPECT_GT(ten.unknowns, 0);
  EXPECT_EQ(ten.newton_per_step, 4); // elastic
  EXPECT_TRUE(ten.symmetric);
  auto twenty = implicit;
  twenty.back() = "time={end_time: 1, dt: 0.05}";
  EXPECT_NEAR(estimate(twenty).seconds / ten.seconds, 2.0, 1e-9);
}

} // namespace
