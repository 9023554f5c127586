// The verification suite's checks decide what their acceptance says, on both sides of every
// bound, and a known failure is shown as such: it fails its bound without failing the suite,
// and passing again (the defect gone) is reported as an unexpected pass that fails the suite
// until the mark is removed.
#include "talus/verify/verification.hpp"

#include <cmath>
#include <gtest/gtest.h>

namespace talus {
namespace {

TEST(VerificationChecks, RelativeAndAbsoluteChecksBoundTheDeviationOnBothSides) {
  EXPECT_TRUE(relative_check("q", 1.009, 1.0, 0.01).passed);
  EXPECT_TRUE(relative_check("q", 0.991, 1.0, 0.01).passed);
  EXPECT_FALSE(relative_check("q", 1.011, 1.0, 0.01).passed);
  EXPECT_FALSE(relative_check("q", 0.989, 1.0, 0.01).passed);
  const Check c = relative_check("q", -2.2, -2.0, 0.2);
  EXPECT_NEAR(c.error, 0.1, 1e-15);
  EXPECT_TRUE(c.passed);
  EXPECT_TRUE(absolute_check("q", 3.0, 3.0, 0.0).passed);
  EXPECT_FALSE(absolute_check("q", 2.0, 3.0, 0.5).passed);
  EXPECT_FALSE(absolute_check("q", 4.0, 3.0, 0.5).passed);
}

TEST(VerificationChecks, BoundsDecideOnTheMeasuredValueAndRefuseNonFiniteValues) {
  EXPECT_TRUE(at_most_check("q", 1.0, 1.0).passed);
  EXPECT_FALSE(at_most_check("q", 1.0001, 1.0).passed);
  EXPECT_TRUE(at_least_check("q", 2.0, 2.0).passed);
  EXPECT_FALSE(at_least_check("q", 1.9999, 2.0).passed);
  EXPECT_TRUE(within_check("q", 2.0, 1.5, 2.5).passed);
  EXPECT_FALSE(within_check("q", 1.4, 1.5, 2.5).passed);
  EXPECT_FALSE(within_check("q", 2.6, 1.5, 2.5).passed);
  for (const double bad : {NAN, INFINITY, -INFINITY}) {
    EXPECT_FALSE(at_most_check("q", bad, 1e300).passed) << bad;
    EXPECT_FALSE(at_least_check("q", bad, -1e300).passed) << bad;
    EXPECT_FALSE(within_check("q", bad, -1e300, 1e300).passed) << bad;
    EXPECT_FALSE(relative_check("q", bad, 1.0, 1e300).passed) << bad;
  }
  EXPECT_TRUE(holds_check("q", true).passed);
  EXPECT_FALSE(holds_check("q", false).passed);
}

TEST(VerificationChecks, VerdictsSeparateKnownFailuresFromPassesAndFailures) {
  EXPECT_EQ(within_check("q", 2.0, 1.0, 3.0).verdict(), Verdict::pass);
  EXPECT_EQ(within_check("q", 5.0, 1.0, 3.0).verdict(), Verdict::fail);
  EXPECT_EQ(report_only("q", 5.0).verdict(), Verdict::report);
  EXPECT_EQ(known_failure(within_check("q", 5.0, 1.0, 3.0), "defect").verdict(),
            Verdict::known_failure);
  EXPECT_EQ(known_failure(within_check("q", 2.0, 1.0, 3.0), "defect").verdict(),
            Verdict::unexpected_pass);
  // A known failure keeps its bound: the reader sees what it should meet.
  const Check k = known_failure(within_check("q", 5.0, 1.0, 3.0), "defect");
  EXPECT_EQ(k.lower, 1.0);
  EXPECT_EQ(k.upper, 3.0);
  EXPECT_EQ(k.known_defect, "defect");
}

TEST(VerificationChecks, ObservedOrderOfAHalvedStep) {
  EXPECT_NEAR(observed_order(4e-3, 1e-3), 2.0, 1e-14);
  EXPECT_NEAR(observed_order(1e-3, 5e-4), 1.0, 1e-14);
}

} // namespace
} // namespace talus
