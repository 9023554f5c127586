// The ghost penalty's face matrix and face selection (include/talus/solver/ghost_penalty.hpp).
#include "talus/solver/ghost_penalty.hpp"

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include <algorithm>
#include <set>

using Ghost2 = talus::GhostPenalty<2>;
using Ghost3 = talus::GhostPenalty<3>;
using talus::ActiveNodes;
using talus::Grid;
using talus::Index;

namespace {

// Every node of the grid as the step's active nodes: node numbers equal lattice ids.
template <int Dim> ActiveNodes<Dim> every_node(const Grid<Dim>& grid) {
  std::vector<Index> ids(static_cast<std::size_t>(grid.node_count()));
  for (std::size_t n = 0; n < ids.size(); ++n)
    ids[n] = static_cast<Index>(n);
  ActiveNodes<Dim> nodes;
  nodes.assign(grid, std::move(ids));
  return nodes;
}

// Values of the field f at the six face nodes: normal coordinate -1, 0, 1 (layers), tangential
// 0, 1, in face_matrix() order (2 * layer + t).
template <class F> Eigen::Matrix<double, 6, 1> face_values(F f) {
  Eigen::Matrix<double, 6, 1> u;
  for (int layer = 0; layer < 3; ++layer)
    for (int t = 0; t < 2; ++t)
      u(2 * layer + t) = f(static_cast<double>(layer - 1), static_cast<double>(t));
  return u;
}

// The same on a 3D face: 3 layers x 4 tangential corners (t0 + 2 t1), face_matrix() order.
template <class F> Eigen::Matrix<double, 12, 1> face_values_3d(F f) {
  Eigen::Matrix<double, 12, 1> u;
  for (int layer = 0; layer < 3; ++layer)
    for (int t = 0; t < 4; ++t)
      u(4 * layer + t) = f(static_cast<double>(layer - 1), static_cast<double>(t & 1),
                           static_cast<double>(t >> 1));
  return u;
}

/// Number of eigenvalues above 1e-12, after checking that none is below -1e-14.
template <class Matrix> int positive_eigenvalues(const Matrix& G) {
  const Eigen::SelfAdjointEigenSolver<Matrix> eig(G);
  int positive = 0;
  for (int k = 0; k < G.rows(); ++k) {
    EXPECT_GT(eig.eigenvalues()(k), -1e-14);
    positive += eig.eigenvalues()(k) > 1e-12;
  }
  return positive;
}

} // namespace

TEST(GhostPenalty, FaceMatrixVanishesOnLinearFieldsOnly) {
  const auto& G = Ghost2::face_matrix();
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
  EXPECT_EQ(positive_eigenvalues(G), 2);
}

TEST(GhostPenalty, FaceMatrix3dVanishesOnTrilinearFieldsWithoutNormalKink) {
  const auto& G = Ghost3::face_matrix();
  // Every field of the trilinear space that is linear in the normal coordinate n.
  for (const auto& u : {face_values_3d([](double, double, double) { return 1.0; }),
                        face_values_3d([](double n, double, double) { return n; }),
                        face_values_3d([](double, double s, double) { return s; }),
                        face_values_3d([](double, double, double t) { return t; }),
                        face_values_3d([](double n, double s, double) { return n * s; }),
                        face_values_3d([](double n, double, double t) { return n * t; }),
                        face_values_3d([](double, double s, double t) { return s * t; }),
                        face_values_3d([](double n, double s, double t) { return n * s * t; })})
    EXPECT_LT((G * u).norm(), 1e-14);
  // The kink |n|: jump 2 over the unit face, 2^2 * 1 = 4; a kink growing along the face,
  // |n| s, jumps by 2 s: int_0^1 int_0^1 4 s^2 = 4 / 3.
  const auto kink = face_values_3d([](double n, double, double) { return std::abs(n); });
  EXPECT_NEAR(kink.dot(G * kink), 4.0, 1e-14);
  const auto ramp = face_values_3d([](double n, double s, double) { return std::abs(n) * s; });
  EXPECT_NEAR(ramp.dot(G * ramp), 4.0 / 3.0, 1e-14);
  EXPECT_LT((G - G.transpose()).norm(), 1e-15);
  EXPECT_EQ(positive_eigenvalues(G), 4); // one jump per tangential corner
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
  Ghost2 ghost;
  ghost.build(every_node(grid), active, modulus, 0.5);
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
  // The same faces when only the nodes the material reaches (and a ring around them) are
  // active and numbered compactly: the selection does not depend on storage over the grid.
  const std::vector<Ghost2::Face> full = ghost.faces();
  std::vector<Index> ids;
  for (Index j = 0; j <= 8; ++j)
    for (Index i = 0; i <= 8; ++i)
      ids.push_back(grid.node_id({i, j}));
  std::sort(ids.begin(), ids.end());
  std::vector<char> some_active;
  std::vector<double> some_modulus;
  for (const Index id : ids) {
    some_active.push_back(active[static_cast<std::size_t>(id)]);
    some_modulus.push_back(modulus[static_cast<std::size_t>(id)]);
  }
  ActiveNodes<2> some;
  some.assign(grid, ids);
  ghost.build(some, some_active, some_modulus, 0.5);
  ASSERT_EQ(ghost.faces().size(), full.size());
  for (std::size_t f = 0; f < full.size(); ++f)
    for (std::size_t k = 0; k < full[f].nodes.size(); ++k)
      EXPECT_EQ(some.lattice_id(ghost.faces()[f].nodes[k]), full[f].nodes[k]);
  ghost.build(every_node(grid), active, modulus, 0.0);
  EXPECT_TRUE(ghost.faces().empty());
}

TEST(GhostPenalty, StabilisesOnlyFacesTouchingTheBoundaryBand3d) {
  // 8^3 cells of h = 0.5; the material covers cells 1..6 in each direction (nodes 1..7).
  const Grid<3> grid(talus::Vec3(0, 0, 0), 0.5, {8, 8, 8});
  std::vector<char> active(static_cast<std::size_t>(grid.node_count()), 0);
  std::vector<double> modulus(active.size(), 0.0);
  for (Index k = 1; k <= 7; ++k)
    for (Index j = 1; j <= 7; ++j)
      for (Index i = 1; i <= 7; ++i) {
        const auto n = static_cast<std::size_t>(grid.node_id({i, j, k}));
        active[n] = 1;
        modulus[n] = 2.0;
      }
  Ghost3 ghost;
  ghost.build(every_node(grid), active, modulus, 0.5);
  // 6^3 active cells; faces between two of them 5 x 6 x 6 per direction, 540; between two
  // interior cells (2..5, no inactive cell among the 26 neighbours) 3 x 4 x 4 per direction,
  // 144: 396 stabilised, each with stiffness gamma E h.
  EXPECT_EQ(ghost.faces().size(), 396u);
  std::set<std::array<Index, 12>> distinct;
  for (const auto& face : ghost.faces()) {
    EXPECT_DOUBLE_EQ(face.stiffness, 0.5 * 2.0 * 0.5);
    for (const Index n : face.nodes)
      EXPECT_TRUE(active[static_cast<std::size_t>(n)]);
    // The nodes form 3 layers along one axis, 4 corners of a unit square across it.
    const auto first = grid.node_ijk(face.nodes[0]);
    const auto last = grid.node_ijk(face.nodes[11]);
    int along = 0, across = 0;
    for (int d = 0; d < 3; ++d) {
      along += last[d] - first[d] == 2;
      across += last[d] - first[d] == 1;
    }
    EXPECT_EQ(along, 1);
    EXPECT_EQ(across, 2);
    distinct.insert(face.nodes);
  }
  EXPECT_EQ(distinct.size(), ghost.faces().size());
}

TEST(GhostPenalty, ASlabBetweenMirrorFacesHasTheBandOfItsSection) {
  // 8 x 8 x 2 cells; the material fills cells 1..6 in x and y and the whole thickness in z
  // (nodes 0..2): a plane-strain slab between the two z faces.
  const Grid<3> grid(talus::Vec3(0, 0, 0), 1.0, {8, 8, 2});
  std::vector<char> active(static_cast<std::size_t>(grid.node_count()), 0);
  std::vector<double> modulus(active.size(), 1.0);
  for (Index k = 0; k <= 2; ++k)
    for (Index j = 1; j <= 7; ++j)
      for (Index i = 1; i <= 7; ++i)
        active[static_cast<std::size_t>(grid.node_id({i, j, k}))] = 1;
  Ghost3 ghost;
  // With rollers on both z faces the band is the 2D one, the outer ring of the 6 x 6 section,
  // in both layers: per layer the 2D test's 36 x- and y-faces, plus the z-faces (one per
  // column of two cells) in the ring, 6^2 - 4^2 = 20: 2 x 36 + 20 = 92.
  ghost.build(every_node(grid), active, modulus, 0.5, {false, false, false, false, true, true});
  EXPECT_EQ(ghost.faces().size(), 92u);
  // Taken for free faces, the z faces put every cell into the band: 2 x 60 + 36 = 156.
  ghost.build(every_node(grid), active, modulus, 0.5);
  EXPECT_EQ(ghost.faces().size(), 156u);
}
