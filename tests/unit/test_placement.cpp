// bodies[i].placement: the lattice offset and the seeded jitter of the material points, as read
// from a case and as built into a scene.
#include "talus/core/errors.hpp"
#include "talus/io/case_reader.hpp"
#include "talus/scene/scene.hpp"

#include <gtest/gtest.h>

namespace talus {
namespace {

// One cell of 0.5 m per direction, 2 x 2 points per cell: lattice spacing 0.25.
const std::string kBlock = R"(name: block
grid: {extent: [2, 2], cell_size: 0.5}
materials:
  - {name: m, model: linear_elastic, density: 1000, youngs_modulus: 1e6, poisson_ratio: 0.3}
bodies:
  - {name: b, material: m, shape: rectangle, min: [0.5, 0.5], max: [1.5, 1.5]}
time: {end_time: 1, cfl: 0.5}
)";

Scene<2> scene_with(const std::vector<std::string>& overrides) {
  return build_scene<2>(read_case_text(kBlock, "case.yaml", overrides));
}

TEST(Placement, DefaultIsTheRegularLattice) {
  const Scene<2> s = scene_with({});
  ASSERT_EQ(s.particles.size(), 16);
  EXPECT_DOUBLE_EQ(s.particles.x[0].x(), 0.625);
  EXPECT_DOUBLE_EQ(s.particles.x[0].y(), 0.625);
}

TEST(Placement, OffsetShiftsTheLatticeInSpacings) {
  const Scene<2> s = scene_with({"bodies[0].placement.offset=[0.25, -0.25]"});
  ASSERT_EQ(s.particles.size(), 16);
  EXPECT_DOUBLE_EQ(s.particles.x[0].x(), 0.625 + 0.0625);
  EXPECT_DOUBLE_EQ(s.particles.x[0].y(), 0.625 - 0.0625);
  EXPECT_EQ(s.particles.x0[0], s.particles.x[0]);
}

TEST(Placement, JitterStaysInTheLatticeCellKeepsVolumesAndRepeatsWithTheSeed) {
  const Scene<2> regular = scene_with({});
  const Scene<2> a = scene_with({"bodies[0].placement.jitter=0.4", "bodies[0].placement.seed=7"});
  const Scene<2> b = scene_with({"bodies[0].placement.jitter=0.4", "bodies[0].placement.seed=7"});
  const Scene<2> c = scene_with({"bodies[0].placement.jitter=0.4", "bodies[0].placement.seed=8"});
  ASSERT_EQ(a.particles.size(), regular.particles.size());
  double largest = 0;
  for (std::size_t p = 0; p < a.particles.x.size(); ++p) {
    const Vec2 moved = a.particles.x[p] - regular.particles.x[p];
    largest = std::max(largest, moved.cwiseAbs().maxCoeff());
    EXPECT_LE(moved.cwiseAbs().maxCoeff(), 0.4 * 0.25 + 1e-15);
    EXPECT_EQ(a.particles.x[p], b.particles.x[p]);
    EXPECT_EQ(a.particles.x0[p], a.particles.x[p]);
    EXPECT_DOUBLE_EQ(a.particles.volume0[p], regular.particles.volume0[p]);
  }
  EXPECT_GT(largest, 0.05); // 32 draws: moved by more than half the allowed 0.1
  EXPECT_NE(a.particles.x[0], c.particles.x[0]);
}

TEST(Placement, OutOfRangeValuesAreInputErrorsAtTheirKey) {
  const std::pair<std::string, std::string> bad[] = {
      {"bodies[0].placement.offset=[0.5, 0]", "bodies[0].placement.offset"},
      {"bodies[0].placement.jitter=0.5", "bodies[0].placement.jitter"},
      {"bodies[0].placement.jitter=-0.1", "bodies[0].placement.jitter"},
      {"bodies[0].placement.seed=-1", "bodies[0].placement.seed"},
      {"bodies[0].placement.spread=1", "bodies[0].placement.spread"},
  };
  for (const auto& [override_text, key] : bad) {
    SCOPED_TRACE(override_text);
    try {
      read_case_text(kBlock, "case.yaml", {override_text});
      ADD_FAILURE() << "expected an InputError";
    } catch (const InputError& e) {
      EXPECT_EQ(e.where().key_path, key) << e.what();
    }
  }
}

} // namespace
} // namespace talus
