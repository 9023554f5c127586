// The Newton rows of the verification cases measure what they claim: the observed order from the
// residual history of newton.log, and a log that is missing or holds no usable pair fails its row
// instead of passing it (the vacuous 1e300 of an earlier version) or dropping it.
#include "../../src/verify/newton_log.hpp"

#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>
#include <string>
#include <unistd.h>

namespace talus::verify_cases {
namespace {

namespace fs = std::filesystem;

class NewtonLog : public ::testing::Test {
protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("talus_newton_log_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path write(const std::string& text) const {
    std::ofstream(dir_ / "newton.log") << text;
    return dir_ / "newton.log";
  }
  fs::path dir_;
};

TEST_F(NewtonLog, TheOrderIsTheWorstLogRatioInTheQuadraticRegime) {
  // 1e-3 -> 1e-6 is order 2, 1e-3 -> 1e-5 order 5/3 (the worst); the pair from 1e-1 starts
  // above 1e-2 and the pair into round-off ends below the floor: neither counts. The abandoned
  // attempt in [...] does not count either.
  const fs::path log =
      write("# step t_end dt converged iterations | residuals\n"
            "1 0.5 0.5 yes 3 | 1e-1 1e-3 1e-6 1e-12\n"
            "2 1 0.5 yes 3 | [plain Newton: 1e-3 0.5; line search:] 1 1e-3 1e-5 1e-10\n");
  const std::optional<double> order = worst_newton_order(log);
  ASSERT_TRUE(order.has_value());
  EXPECT_NEAR(*order, 5.0 / 3.0, 1e-12);
  EXPECT_FALSE(newton_order_check("order", log, 1.8, "").passed);
  EXPECT_TRUE(newton_order_check("order", log, 1.6, "").passed);
}

TEST_F(NewtonLog, ALogThatMeasuresNothingFailsItsRow) {
  // Linear steps converge in one iterate: no pair lies between 1e-2 and the floor.
  const fs::path log = write("1 1 1 yes 1 | 1e0 1e-11\n");
  EXPECT_FALSE(worst_newton_order(log).has_value());
  const Check c = newton_order_check("order", log, 1.8, "");
  EXPECT_FALSE(c.passed);
  EXPECT_EQ(c.verdict(), Verdict::fail);
  EXPECT_FALSE(newton_order_check("order", dir_ / "missing.log", 1.8, "").passed);
}

TEST_F(NewtonLog, IterationRowsTakeTheirQuantileAndFailWithoutAConvergedStep) {
  write("# header\n1 0.25 0.25 yes 4 | 1 1e-3 1e-6 1e-10\n2 0.5 0.25 no 30 | 1 1\n"
        "2 0.5 0.125 yes 9 | 1\n3 0.75 0.25 yes 5 | 1\n4 1 0.25 yes 7 | 1\n");
  const std::vector<int> its = newton_iterations(dir_, 3);
  EXPECT_EQ(its, (std::vector<int>{4, 9, 5}));
  EXPECT_TRUE(newton_iterations_check("median", its, 0.5, 5, "").passed);
  EXPECT_FALSE(newton_iterations_check("median", its, 0.5, 4.9, "").passed);
  EXPECT_TRUE(newton_iterations_check("largest", its, 1.0, 9, "").passed);
  EXPECT_FALSE(newton_iterations_check("largest", its, 1.0, 8.9, "").passed);
  EXPECT_FALSE(newton_iterations_check("median", {}, 0.5, 8, "").passed);
  EXPECT_TRUE(newton_iterations(dir_ / "missing", 3).empty());
}

} // namespace
} // namespace talus::verify_cases
