// Assembly by shares (include/talus/linalg/dof_map.hpp, ImplicitShareAssembly::assemble_share): the
// residual and tangent of the cantilever assembled as two shares of its points, scattered to
// global DOFs and summed, equal the one-share (serial) assembly; every DOF is owned by exactly
// one share; a share whose DOF map lacks one of its ghost nodes is refused.
#include "../../src/solver/implicit_share_assembly.hpp"
#include "talus/io/case_reader.hpp"
#include "talus/linalg/dof_map.hpp"
#include "talus/scene/scene.hpp"
#include "talus/solver/implicit_solver.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

using namespace talus;

namespace {

// The talk's cantilever (cases/cantilever.yaml) in Hencky elasticity, so that the tangent has
// a geometric part, with the analysis and the solver keys of each test appended.
std::string cantilever(const std::string& analysis, const std::string& solver) {
  return R"(name: cantilever
analysis: )" +
         analysis +
         R"(
grid:
  origin: [0, -1.5]
  extent: [10, 3]
  cell_size: 0.125
materials:
  - {name: beam, model: hencky, density: 1000, youngs_modulus: 3.0e5, poisson_ratio: 0.3}
bodies:
  - {name: beam, material: beam, shape: rectangle, min: [0, -0.5], max: [8, 0.5],
     particles_per_cell: 2, velocity: ["0.01 * x", "-0.02 * x"]}
boundaries: {x_min: fixed}
tractions:
  - {body: beam, side: right, traction: [0, -100.0]}
time: {end_time: 1, dt: 0.05}
output: {every_steps: 1}
solver: )" +
         solver + "\n";
}

struct Assembly {
  Eigen::VectorXd residual;
  SparseMatrix tangent;
};

/// The residual and tangent at the global increment du, assembled share by share and summed.
Assembly assemble_in_shares(ImplicitShareAssembly& solver, const std::vector<ParticleShare>& shares,
                            const Eigen::VectorXd& du) {
  const Index n = solver.unknowns();
  Assembly sum{Eigen::VectorXd::Zero(n), SparseMatrix(n, n)};
  const std::vector<int> owners = solver.node_owners(shares);
  for (const ParticleShare& share : shares) {
    const DofMap map = solver.dof_map(share, owners);
    Eigen::VectorXd r;
    SparseMatrix tangent;
    EXPECT_TRUE(solver.assemble_share(share, map, map.restrict_to_overlap(du), &r, &tangent));
    map.add_to_global(r, sum.residual);
    map.add_to_global(tangent, sum.tangent);
  }
  return sum;
}

/// Largest absolute entry of a sparse matrix.
double max_abs(const SparseMatrix& A) {
  double m = 0;
  for (int k = 0; k < A.nonZeros(); ++k)
    m = std::max(m, std::abs(A.valuePtr()[k]));
  return m;
}

/// A solver prepared for the full load step at a random increment of up to 1 % of a cell, so
/// that every point is strained and the residual is far from zero.
struct Prepared {
  explicit Prepared(const std::string& text) : scene(build_scene<2>(read_case_text(text, "test"))) {
    solver = make_implicit_solver(scene);
    share_assembly(*solver).prepare(1.0, 1.0, 0.05);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> d(-1e-3, 1e-3);
    du = Eigen::VectorXd::NullaryExpr(solver->unknowns(), [&] { return d(rng); });
  }
  Scene<2> scene;
  std::unique_ptr<ImplicitSolver> solver;
  Eigen::VectorXd du;
};

// Two shares sum the same terms as one, in another order: each entry is a sum of a few dozen
// terms, so the shares differ from the serial assembly by a few ulps of the largest entry.
// 1e-12 allows thousands of ulps, and is still far below what one missing or doubled point or
// face would change (about 1e-3 of an entry or more).
void expect_two_shares_equal_one(const std::string& text) {
  Prepared run(text);
  ImplicitShareAssembly& solver = share_assembly(*run.solver);
  const Index np = run.scene.particles.size();
  ASSERT_GT(solver.unknowns(), 0);
  const Assembly one = assemble_in_shares(solver, split_particles(np, 1), run.du);
  const Assembly two = assemble_in_shares(solver, split_particles(np, 2), run.du);
  const double r_scale = one.residual.lpNorm<Eigen::Infinity>();
  ASSERT_GT(r_scale, 0.0);
  EXPECT_LE((two.residual - one.residual).lpNorm<Eigen::Infinity>(), 1e-12 * r_scale);
  EXPECT_LE(max_abs(SparseMatrix(two.tangent - one.tangent)), 1e-12 * max_abs(one.tangent));
}

} // namespace

TEST(DofMap, TwoSharesSumToOneStatic) {
  // The ghost penalty is on by default (1e-3); off here.
  expect_two_shares_equal_one(
      cantilever("implicit_quasistatic", "{shape: gimp, ghost_penalty: 0}"));
}

TEST(DofMap, TwoSharesSumToOneStaticGhostPenalty) {
  // gamma = 0.1 makes the faces' terms a visible part of the tangent (see above).
  expect_two_shares_equal_one(
      cantilever("implicit_quasistatic", "{shape: gimp, ghost_penalty: 0.1}"));
}

TEST(DofMap, TwoSharesSumToOneDynamicGhostPenalty) {
  expect_two_shares_equal_one(cantilever("implicit_dynamic", "{shape: gimp, ghost_penalty: 0.1}"));
}

TEST(DofMap, EachDofOwnedExactlyOnce) {
  Prepared run(cantilever("implicit_quasistatic", "{shape: gimp, ghost_penalty: 0.1}"));
  ImplicitShareAssembly& solver = share_assembly(*run.solver);
  for (const int count : {1, 2, 3}) {
    const auto shares = split_particles(run.scene.particles.size(), count);
    const std::vector<int> owners = solver.node_owners(shares);
    std::vector<int> owned(static_cast<std::size_t>(solver.unknowns()), 0);
    for (const ParticleShare& share : shares) {
      const DofMap map = solver.dof_map(share, owners);
      for (const Index gid : map.owned_gids())
        ++owned[static_cast<std::size_t>(gid)];
      // Local ids: the owned DOFs, then the ghosts, each ascending.
      const auto& gids = map.overlap_gids();
      const auto ghosts_begin = gids.begin() + map.owned_count();
      EXPECT_TRUE(std::is_sorted(gids.begin(), ghosts_begin));
      EXPECT_TRUE(std::is_sorted(ghosts_begin, gids.end()));
      // Shares after the first meet the points before them: they have ghosts.
      if (share.index > 0) {
        EXPECT_GT(map.overlap_count(), map.owned_count());
      }
      if (count == 1) { // one share numbers its DOFs as the global numbering
        ASSERT_EQ(map.overlap_count(), solver.unknowns());
        for (std::size_t l = 0; l < gids.size(); ++l)
          EXPECT_EQ(gids[l], static_cast<Index>(l));
      }
    }
    EXPECT_TRUE(std::all_of(owned.begin(), owned.end(), [](int n) { return n == 1; }))
        << count << " shares";
  }
}

TEST(DofMap, RefusesAShareMissingAGhostNode) {
  Prepared run(cantilever("implicit_quasistatic", "{shape: gimp, ghost_penalty: 0.1}"));
  ImplicitShareAssembly& solver = share_assembly(*run.solver);
  const auto shares = split_particles(run.scene.particles.size(), 2);
  const std::vector<int> owners = solver.node_owners(shares);
  const ParticleShare& second = shares[1];
  std::vector<Index> nodes = solver.touched_nodes(second, owners);
  // Drop a ghost node: one the second share reaches but the first owns.
  const auto ghost = std::find_if(nodes.begin(), nodes.end(), [&](Index n) {
    return owners[static_cast<std::size_t>(n)] == 0;
  });
  ASSERT_NE(ghost, nodes.end());
  const Index missing = *ghost;
  nodes.erase(ghost);
  const DofMap incomplete(second.index, nodes, solver.global_dofs(), owners);
  EXPECT_FALSE(incomplete.in_overlap(missing));
  Eigen::VectorXd r;
  try {
    solver.assemble_share(second, incomplete, incomplete.restrict_to_overlap(run.du), &r, nullptr);
    FAIL() << "a share without its ghost node " << missing << " was assembled";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("grid node " + std::to_string(missing)), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("not in its DOF map"), std::string::npos) << e.what();
  }
}

// F-bar couples the points of a cell through their average volume change: a share that holds
// only part of a cell cannot assemble it, and says so instead of assembling a wrong tangent.
TEST(DofMap, FBarRefusesASplitCell) {
  Prepared run(cantilever("implicit_quasistatic", "{shape: gimp, f_bar: true}"));
  ImplicitShareAssembly& solver = share_assembly(*run.solver);
  // The first point alone: its cell holds four (2 x 2 points per cell).
  const std::vector<ParticleShare> shares = {{0, 0, 1}, {1, 1, run.scene.particles.size()}};
  const std::vector<int> owners = solver.node_owners(shares);
  const DofMap map = solver.dof_map(shares[0], owners);
  Eigen::VectorXd r;
  try {
    solver.assemble_share(shares[0], map, map.restrict_to_overlap(run.du), &r, nullptr);
    FAIL() << "a share holding part of a cell was assembled with F-bar";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("F-bar needs shares made of whole cells"),
              std::string::npos)
        << e.what();
  }
}
