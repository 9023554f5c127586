// A node layout with more than Dim unknowns per node, through the implicit solver's assembler
// and DOF map: a toy Biot-like problem on bilinear cells, the displacement's two components and
// a scalar diffusion field per node, with displacement-displacement, pressure-pressure and both
// coupling blocks per cell. The lattice assembler's matrix must equal, entry for entry, a dense
// matrix built by hand from the same blocks through dof(node, field, component) alone, and
// hold exactly the entries of the node pairs a cell couples (every field with every field).
#include "talus/linalg/dof_map.hpp"
#include "talus/linalg/lattice_assembler.hpp"
#include "talus/linalg/node_layout.hpp"
#include "talus/solver/rigid_body_modes.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <set>
#include <utility>
#include <vector>

using talus::ActiveNodes;
using talus::DofMap;
using talus::Grid;
using talus::Index;
using talus::LatticeAssembler;
using talus::NodeDofs;
using talus::NodeLayout;

namespace {

constexpr int kU = NodeLayout::kDisplacement;

struct TwoFieldProblem {
  Grid<2> grid{talus::Vec<2>::Zero(), 0.5, {3, 2}};
  ActiveNodes<2> nodes;
  NodeLayout layout{2};
  int pressure = -1;
  NodeDofs dofs;
  std::vector<std::array<Index, 4>> cells; ///< node numbers of each cell's corners
  Index unknowns = 0;

  TwoFieldProblem() {
    pressure = layout.add_field("pressure", 1);
    std::vector<Index> corners; // the nodes of the 3 x 2 cells
    for (Index j = 0; j <= grid.cells(1); ++j)
      for (Index i = 0; i <= grid.cells(0); ++i)
        corners.push_back(grid.node_id({i, j}));
    std::sort(corners.begin(), corners.end());
    nodes.assign(grid, corners);
    dofs = NodeDofs(layout);
    dofs.reset(nodes.size());
    // Node by node, field by field; the bottom row's displacement held (a fixed base) and the
    // top row's pressure prescribed (a drained surface): nodes with and without every field.
    for (Index n = 0; n < nodes.size(); ++n) {
      const auto ijk = nodes.ijk(n);
      const bool base = ijk[1] == 0, top = ijk[1] == grid.cells(1);
      if (!base)
        for (int a = 0; a < 2; ++a)
          dofs.set(n, kU, a, unknowns++);
      if (!top)
        dofs.set(n, pressure, 0, unknowns++);
    }
    for (Index j = 0; j < grid.cells(1); ++j)
      for (Index i = 0; i < grid.cells(0); ++i)
        cells.push_back({node(i, j), node(i + 1, j), node(i, j + 1), node(i + 1, j + 1)});
  }
  Index node(Index i, Index j) const { return nodes.find_lattice_id(grid.node_id({i, j})); }
};

/// A cell's blocks, different in every cell and every entry so that a misplaced term shows.
struct CellBlocks {
  Eigen::MatrixXd uu, pp, up, pu;
};
CellBlocks blocks_of(std::size_t cell) {
  const double s = 1.0 + 0.25 * static_cast<double>(cell);
  CellBlocks b;
  b.uu.resize(8, 8);
  b.pp.resize(4, 4);
  b.up.resize(8, 4);
  b.pu.resize(4, 8);
  for (Eigen::Index i = 0; i < 8; ++i)
    for (Eigen::Index j = 0; j < 8; ++j)
      b.uu(i, j) = s * (100.0 + static_cast<double>(8 * i + j));
  for (Eigen::Index i = 0; i < 4; ++i)
    for (Eigen::Index j = 0; j < 4; ++j)
      b.pp(i, j) = s * (-1000.0 - static_cast<double>(4 * i + j));
  for (Eigen::Index i = 0; i < 8; ++i)
    for (Eigen::Index j = 0; j < 4; ++j) {
      b.up(i, j) = s * (0.5 + static_cast<double>(4 * i + j));
      b.pu(j, i) = -s * (7.0 + static_cast<double>(8 * j + i));
    }
  return b;
}

/// The hand-built matrix: each block's term (k, a; l, b) goes to row dof(node k, row field, a)
/// and column dof(node l, column field, b) when both exist.
void add_by_hand(Eigen::MatrixXd& A, const NodeDofs& dofs, const std::array<Index, 4>& cell,
                 int row_field, int col_field, const Eigen::MatrixXd& K) {
  const int rc = dofs.layout().components(row_field), cc = dofs.layout().components(col_field);
  for (int k = 0; k < 4; ++k)
    for (int a = 0; a < rc; ++a)
      for (int l = 0; l < 4; ++l)
        for (int b = 0; b < cc; ++b) {
          const Index row = dofs.dof(cell[k], row_field, a), col = dofs.dof(cell[l], col_field, b);
          if (row >= 0 && col >= 0)
            A(row, col) += K(rc * k + a, cc * l + b);
        }
}

} // namespace

TEST(NodeLayout, NumbersFieldsAfterTheDisplacement) {
  NodeLayout layout(3);
  EXPECT_EQ(layout.width(), 3);
  const int p = layout.add_field("pore_pressure", 1);
  const int v = layout.add_field("body_1_velocity", 3);
  EXPECT_EQ(layout.fields(), 3);
  EXPECT_EQ(layout.width(), 7);
  EXPECT_EQ(layout.offset(p), 3);
  EXPECT_EQ(layout.offset(v), 4);
  EXPECT_EQ(layout.find("pore_pressure"), p);
  EXPECT_EQ(layout.find("temperature"), -1);
  EXPECT_EQ(layout.slot(2, v, 1), 2u * 7u + 5u);
  EXPECT_THROW(layout.add_field("nothing", 0), std::invalid_argument);
}

TEST(TwoFieldAssembly, EqualsTheHandBuiltMatrix) {
  const TwoFieldProblem problem;
  const NodeDofs& dofs = problem.dofs;
  // One share owning every node numbers its local unknowns as the global ones.
  const std::vector<int> owner(static_cast<std::size_t>(problem.nodes.size()), 0);
  std::vector<Index> all(static_cast<std::size_t>(problem.nodes.size()));
  for (Index n = 0; n < problem.nodes.size(); ++n)
    all[static_cast<std::size_t>(n)] = n;
  const DofMap map(0, all, dofs, owner);
  ASSERT_EQ(map.overlap_count(), problem.unknowns);
  for (Index n = 0; n < problem.nodes.size(); ++n) {
    for (int a = 0; a < 2; ++a)
      EXPECT_EQ(map.local_dof(n, kU, a), dofs.dof(n, kU, a));
    EXPECT_EQ(map.local_dof(n, problem.pressure, 0), dofs.dof(n, problem.pressure, 0));
  }

  LatticeAssembler<2> assembler;
  const auto cliques = [&](auto&& f) {
    for (const auto& cell : problem.cells)
      f(std::span<const Index>(cell));
  };
  assembler.build(
      problem.nodes, map.layout(), map.overlap_count(),
      [&](Index n, int k) { return map.local_dof_at(n, k); }, cliques);
  Eigen::MatrixXd by_hand = Eigen::MatrixXd::Zero(problem.unknowns, problem.unknowns);
  for (std::size_t c = 0; c < problem.cells.size(); ++c) {
    const auto& cell = problem.cells[c];
    const CellBlocks b = blocks_of(c);
    assembler.add_block(cell, b.uu);
    assembler.add_block(cell, b.pp, problem.pressure);
    assembler.add_coupling_block(cell, kU, problem.pressure, b.up);
    assembler.add_coupling_block(cell, problem.pressure, kU, b.pu);
    add_by_hand(by_hand, dofs, cell, kU, kU, b.uu);
    add_by_hand(by_hand, dofs, cell, problem.pressure, problem.pressure, b.pp);
    add_by_hand(by_hand, dofs, cell, kU, problem.pressure, b.up);
    add_by_hand(by_hand, dofs, cell, problem.pressure, kU, b.pu);
  }
  const Eigen::MatrixXd assembled(assembler.finish());
  // The same terms in the same order per entry: equal to the last bit.
  EXPECT_EQ((assembled - by_hand).cwiseAbs().maxCoeff(), 0.0);

  // The structure: exactly the unknowns of node pairs that share a cell.
  std::set<std::pair<Index, Index>> coupled;
  for (const auto& cell : problem.cells)
    for (const Index k : cell)
      for (const Index l : cell)
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j)
            if (const Index r = dofs.dof(k, i), c = dofs.dof(l, j); r >= 0 && c >= 0)
              coupled.insert({r, c});
  EXPECT_EQ(static_cast<std::size_t>(assembler.finish().nonZeros()), coupled.size());
  // Every field's block reached the matrix: a coupling term of the first cell in place.
  const Index u_row = dofs.dof(problem.node(1, 1), kU, 1);
  const Index p_col = dofs.dof(problem.node(0, 0), problem.pressure, 0);
  ASSERT_GE(u_row, 0);
  ASSERT_GE(p_col, 0);
  EXPECT_NE(assembled(u_row, p_col), 0.0);
}

TEST(TwoFieldAssembly, RefusesABlockOfTheWrongField) {
  const TwoFieldProblem problem;
  LatticeAssembler<2> assembler;
  assembler.build(
      problem.nodes, problem.layout, problem.unknowns,
      [&](Index n, int k) { return problem.dofs.dof(n, k); },
      [&](auto&& f) {
        for (const auto& cell : problem.cells)
          f(std::span<const Index>(cell));
      });
  const auto& cell = problem.cells.front();
  // A displacement-sized block offered as the pressure's, and a coupling block transposed.
  EXPECT_THROW(assembler.add_block(cell, Eigen::MatrixXd::Zero(8, 8), problem.pressure),
               std::invalid_argument);
  EXPECT_THROW(
      assembler.add_coupling_block(cell, kU, problem.pressure, Eigen::MatrixXd::Zero(4, 8)),
      std::invalid_argument);
}

// The solver's view of the block structure (near_null_space, handed to MueLu): the
// displacement's rigid-body modes, then a constant on the pressure's unknowns, which a pure-flux
// diffusion operator annihilates. Without the constant column (the rigid modes alone, zero on
// the pressure rows) the pressure's block would be interpolated by nothing.
TEST(TwoFieldAssembly, NearNullSpaceHasAConstantPerScalarField) {
  const TwoFieldProblem problem;
  const NodeDofs& dofs = problem.dofs;
  const Eigen::MatrixXd rigid =
      talus::rigid_body_modes<2, false>(problem.nodes, dofs, problem.unknowns);
  const Eigen::MatrixXd modes =
      talus::near_null_space<2, false>(problem.nodes, dofs, problem.unknowns);
  ASSERT_EQ(modes.cols(), rigid.cols() + 1);
  EXPECT_EQ(modes.leftCols(rigid.cols()), rigid);
  const Eigen::VectorXd constant = modes.col(rigid.cols());
  Index pressures = 0;
  for (Index n = 0; n < problem.nodes.size(); ++n) {
    for (int a = 0; a < 2; ++a) {
      if (const Index d = dofs.dof(n, kU, a); d >= 0) {
        EXPECT_EQ(constant[d], 0.0);
      }
    }
    if (const Index d = dofs.dof(n, problem.pressure, 0); d >= 0) {
      EXPECT_EQ(constant[d], 1.0);
      ++pressures;
    }
  }
  EXPECT_EQ(constant.sum(), static_cast<double>(pressures));
  // A bilinear cell's diffusion matrix (unit square, corners (0,0), (1,0), (0,1), (1,1)),
  // assembled with every component of every node free (a pure-flux problem): K 1 = 0.
  Eigen::Matrix4d laplace;
  laplace << 4, -1, -1, -2, -1, 4, -2, -1, -1, -2, 4, -1, -2, -1, -1, 4;
  laplace /= 6.0;
  NodeDofs free(problem.layout);
  free.reset(problem.nodes.size());
  for (Index n = 0; n < problem.nodes.size(); ++n)
    for (int k = 0; k < 3; ++k)
      free.set(n, k < 2 ? kU : problem.pressure, k < 2 ? k : 0, 3 * n + k);
  const Index size = 3 * problem.nodes.size();
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(size, size);
  for (const auto& cell : problem.cells)
    add_by_hand(A, free, cell, problem.pressure, problem.pressure, laplace);
  const Eigen::MatrixXd free_modes = talus::near_null_space<2, false>(problem.nodes, free, size);
  ASSERT_EQ(free_modes.cols(), 4); // two translations, the rotation, the constant
  EXPECT_LT((A * free_modes).cwiseAbs().maxCoeff(), 1e-14);
  // Not vacuous: the operator moves a single pressure.
  EXPECT_GT((A * Eigen::VectorXd::Unit(size, free.dof(0, problem.pressure, 0))).norm(), 0.5);
}
