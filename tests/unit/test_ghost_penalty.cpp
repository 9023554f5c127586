// The ghost penalty's face matrix and face selection (include/talus/solver/ghost_penalty.hpp).
#include "talus/solver/ghost_penalty.hpp"

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include <set>

using talus::GhostPenalty;
using talus::Grid;
using talus::Index;

namespace {

// Values of the field f at the six face nodes: normal coordinate -1, 0, 1 (layers), tangential
// 0, 1, in face_matrix() order (2 * layer + t).
template <class F> Eigen::Matrix<double, 6, 1> face_values(F f) {
  Eigen::Matrix<double, 6, 1> u;
  for (int layer = 0; layer < 3; ++layer)
    for (int t = 0; t < 2; ++t)
      u(2 * layer + t) = f(static_cast<double>(layer - 1), static_cast<double>(t));
  return u;
}

} // namespace

TEST(GhostPenalty, FaceMatrixVanishesOnLinearFieldsOnly) {
  const auto& G = GhostPenalty::face_matrix();
  // Linear fields (and the bilinear n t, which has no normal-derivative jump) are untouched.
  for (const auto& u : {face_values([](double, double) { return 1.0; }),
                        face_values([](double n, double) { return n; }),
                        face_values([](double, double t) { return t; }),
                        face_values([](double n, double t) { return n * t; })})
    EXPECT_LT((G * u).norm(), 1e-14);
  // A kink across the face (|n|, unit spacing): the normal derivative jumps by 2 all along the
  // face, so u^T G u = 2^2 * int_0^1 deta = 4.
  const auto kink = face_values([](double n, double) { return std::abs(n); });
  EXPECT_NEAR(kink.dot(G * kink), 4.0, 1e-14);
  // Symmetric positive semi-definite of rank 2: one jump per tangential node.
  EXPECT_LT((G - G.transpose()).norm(), 1e-15);
  const Eigen::SelfAdjointEigenSolver<GhostPenalty::FaceMatrix> eig(G);
  int positive = 0;
  for (int k = 0; k < 6; ++k) {
    EXPECT_GT(eig.eigenvalues()(k), -1e-14);
    positive += eig.eigenvalues()(k) > 1e-12;
  }
  EXPECT_EQ(positive, 2);
}

TEST(GhostPenalty, StabilisesOnlyFacesTouchingTheBoundaryBand) {
  // 8 x 8 cells; the material covers cells 1..6 in both directions (nodes 1..7 active).
  const Grid<2> grid(talus::Vec2(0, 0), 1.0, {8, 8});
  std::vector<char> active(static_cast<std::size_t>(grid.node_count()), 0);
  std::vector<double> modulus(active.size(), 0.0);
  for (Index j = 1; j <= 7; ++j)
    for (Index i = 1; i <= 7; ++i) {
      const auto n = static_cast<std::size_t>(grid.node_id({i, j}));
      active[n] = 1;
      modulus[n] = 2.0;
    }
  GhostPenalty ghost;
  ghost.build(grid, active, modulus, 0.5);
  // Active cells: lower-left node 1..6 in each direction, 6 x 6. Faces between two active
  // cells: 5 x 6 per direction, 60. The band is the outer ring (an inactive cell among the
  // eight neighbours); a face is skipped only between two interior cells (2..5): 3 x 4 per
  // direction, 24. So 36 faces are stabilised.
  EXPECT_EQ(ghost.faces().size(), 36u);
  for (const auto& face : ghost.faces()) {
    EXPECT_DOUBLE_EQ(face.stiffness, 0.5 * 2.0);
    for (const Index n : face.nodes)
      EXPECT_TRUE(active[static_cast<std::size_t>(n)]);
  }
  ghost.build(grid, active, modulus, 0.0);
  EXPECT_TRUE(ghost.faces().empty());
}
