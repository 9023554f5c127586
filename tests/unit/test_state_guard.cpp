// The state guard's checks on hand-made states: every guarded field is caught, the lowest-index
// offender is named (deterministic for any thread count), a healthy state passes.
#include "talus/solver/state_guard.hpp"

#include <gtest/gtest.h>

#include <limits>

using talus::embedded;
using talus::Index;
using talus::Mat2;
using talus::Mat3;
using talus::Particles;
using talus::Vec2;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

/// Four healthy points: stretched (det F = 1.2), stressed, moving.
Particles<2> healthy() {
  Particles<2> P;
  P.resize(4);
  for (std::size_t s = 0; s < 4; ++s) {
    P.x0[s] = Vec2(0.1 * static_cast<double>(s), 0.5);
    P.x[s] = P.x0[s];
    P.v[s] = Vec2(1.0, -2.0);
    P.F[s] = embedded<2>((Mat2() << 1.2, 0.1, 0.0, 1.0).finished());
    P.stress[s] = 3.0 * Mat3::Identity();
  }
  return P;
}

} // namespace

TEST(StateGuard, HealthyStatePasses) {
  EXPECT_FALSE(talus::find_particle_violation(healthy()).has_value());
}

TEST(StateGuard, EveryParticleFieldIsGuarded) {
  struct Breakage {
    const char* field;
    void (*apply)(Particles<2>&, std::size_t);
    double value;
  };
  const Breakage cases[] = {
      {"velocity", [](Particles<2>& P, std::size_t s) { P.v[s].y() = kNaN; }, kNaN},
      {"position", [](Particles<2>& P, std::size_t s) { P.x[s].x() = kInf; }, kInf},
      {"F", [](Particles<2>& P, std::size_t s) { P.F[s](1, 0) = -kInf; }, -kInf},
      {"det F",
       [](Particles<2>& P, std::size_t s) { P.F[s] = embedded<2>(Vec2(0.5, -0.2).asDiagonal()); },
       -0.1},
      {"det F", [](Particles<2>& P, std::size_t s) { P.F[s].topLeftCorner<2, 2>().setZero(); },
       0.0},
      {"det F",
       [](Particles<2>& P, std::size_t s) { P.F[s] = embedded<2>(Vec2(0.01, 0.005).asDiagonal()); },
       5e-5},
      {"stress", [](Particles<2>& P, std::size_t s) { P.stress[s](2, 2) = kNaN; }, kNaN},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.field);
    Particles<2> P = healthy();
    // Two offenders: the lower index is reported.
    c.apply(P, 3);
    c.apply(P, 2);
    const auto v = talus::find_particle_violation(P);
    ASSERT_TRUE(v.has_value());
    EXPECT_EQ(v->field, c.field);
    EXPECT_FALSE(v->on_node);
    EXPECT_EQ(v->index, 2);
    EXPECT_EQ(v->position, talus::padded<2>(P.x0[2]));
    if (std::isnan(c.value))
      EXPECT_TRUE(std::isnan(v->value));
    else
      EXPECT_DOUBLE_EQ(v->value, c.value);
    const std::string text = v->describe();
    EXPECT_NE(text.find(std::string(c.field) + " = "), std::string::npos) << text;
    EXPECT_NE(text.find("particle 2 (initial position (0.2, 0.5))"), std::string::npos) << text;
  }
}

TEST(StateGuard, GridNodesAreNamedWithTheirPosition) {
  const talus::Grid<2> grid(Vec2(0, 0), 0.5, {4, 4});
  // Three active nodes, the field one entry per active node.
  const Index bad = grid.node_id({2, 3});
  talus::ActiveNodes<2> nodes;
  nodes.assign(grid, {grid.node_id({0, 0}), bad, grid.node_id({4, 4})});
  std::vector<Vec2> velocity(3, Vec2(1, 1));
  velocity[1].x() = kNaN;
  const auto v = talus::find_node_violation<2>(nodes, velocity, "grid velocity");
  ASSERT_TRUE(v.has_value());
  EXPECT_TRUE(v->on_node);
  EXPECT_EQ(v->index, bad); // named by its lattice id, not its place among the active nodes
  EXPECT_EQ(v->position, talus::Vec3(1.0, 1.5, 0.0));
  EXPECT_NE(v->describe().find("grid velocity = nan is not finite at grid node"), std::string::npos)
      << v->describe();
  velocity[1].x() = 1.0;
  EXPECT_FALSE(talus::find_node_violation<2>(nodes, velocity, "grid velocity").has_value());
}
