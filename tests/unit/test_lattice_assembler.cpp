// LatticeAssembler (include/talus/linalg/lattice_assembler.hpp) against a dense matrix summed
// from the same blocks in the same order: equal entry for entry, no more nonzeros than coupled
// pairs, rows ascending in every column; the same structure is recognised as such; blocks
// outside the declared structure and node unknowns that are not consecutive are refused.
#include "talus/linalg/lattice_assembler.hpp"

#include <gtest/gtest.h>

#include <map>
#include <random>
#include <set>
#include <stdexcept>
#include <vector>

using talus::ActiveNodes;
using talus::Grid;
using talus::Index;
using talus::LatticeAssembler;

namespace {

/// Unknowns numbered node by node in a shuffled node order, a few components held (no
/// unknown) as at fixed and roller boundaries, and nodes outside every clique left out.
template <int Dim> struct Numbering {
  std::vector<Index> dof; // per node and component, -1 for none
  Index size = 0;
  Index operator()(Index n, int a) const { return dof[static_cast<std::size_t>(Dim * n + a)]; }
};

/// The cliques are in node numbers of `nodes`: the nodes some clique reaches, numbered in
/// lattice order as a step's active nodes are.
template <int Dim> struct Problem {
  Grid<Dim> grid;
  std::vector<std::vector<Index>> cliques;
  Numbering<Dim> numbering;
  ActiveNodes<Dim> nodes;
};

/// Cliques as an MPM step has them: the W^Dim stencils of points (W = 2 or 3), the 2 x 3^(Dim-1)
/// nodes of a ghost-penalty face, and 4^Dim-node F-bar patches, at random places on the grid.
template <int Dim> Problem<Dim> random_problem(std::mt19937& rng) {
  std::array<Index, Dim> cells;
  cells.fill(Dim == 2 ? 9 : 5);
  Problem<Dim> p{Grid<Dim>(talus::Vec<Dim>::Zero(), 1.0, cells), {}, {}, {}};
  auto box = [&](std::array<Index, Dim> lo, std::array<Index, Dim> width) {
    std::vector<Index> nodes;
    std::array<Index, Dim> ijk{};
    const auto count = [&] {
      Index c = 1;
      for (int d = 0; d < Dim; ++d)
        c *= width[d];
      return c;
    }();
    for (Index k = 0; k < count; ++k) {
      Index rest = k;
      for (int d = 0; d < Dim; ++d) {
        ijk[d] = lo[d] + rest % width[d];
        rest /= width[d];
      }
      nodes.push_back(p.grid.node_id(ijk));
    }
    return nodes;
  };
  for (int c = 0; c < 60; ++c) {
    const int kind = static_cast<int>(rng() % 3);
    std::array<Index, Dim> width;
    width.fill(kind == 0 ? 3 : kind == 1 ? 2 : 4);
    if (kind == 1) // a face: two nodes across it, three along it
      for (int d = 1; d < Dim; ++d)
        width[d] = 3;
    std::array<Index, Dim> lo;
    for (int d = 0; d < Dim; ++d)
      lo[d] = -1 + static_cast<Index>(rng() % static_cast<unsigned>(cells[d] + 3 - width[d]));
    p.cliques.push_back(box(lo, width));
  }
  std::set<Index> used;
  for (const auto& c : p.cliques)
    used.insert(c.begin(), c.end());
  p.nodes.assign(p.grid, std::vector<Index>(used.begin(), used.end()));
  for (auto& c : p.cliques)
    for (Index& n : c)
      n = p.nodes.find_lattice_id(n);
  std::vector<Index> order(static_cast<std::size_t>(p.nodes.size()));
  for (std::size_t n = 0; n < order.size(); ++n)
    order[n] = static_cast<Index>(n);
  std::shuffle(order.begin(), order.end(), rng);
  p.numbering.dof.assign(static_cast<std::size_t>(Dim * p.nodes.size()), -1);
  for (const Index n : order)
    for (int a = 0; a < Dim; ++a)
      if (rng() % 7 != 0) // about one component in seven held
        p.numbering.dof[static_cast<std::size_t>(Dim * n + a)] = p.numbering.size++;
  return p;
}

template <int Dim> void build(LatticeAssembler<Dim>& assembler, const Problem<Dim>& p) {
  assembler.build(p.nodes, talus::NodeLayout(Dim), p.numbering.size, p.numbering, [&](auto&& f) {
    for (const auto& c : p.cliques)
      f(std::span<const Index>(c));
  });
}

Eigen::MatrixXd random_block(Eigen::Index n, std::mt19937& rng) {
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  Eigen::MatrixXd K(n, n);
  for (Eigen::Index k = 0; k < K.size(); ++k)
    K.data()[k] = value(rng);
  return K;
}

template <int Dim> void check_against_dense(std::uint32_t seed) {
  std::mt19937 rng(seed);
  const Problem<Dim> p = random_problem<Dim>(rng);
  LatticeAssembler<Dim> assembler;
  build(assembler, p);
  const auto n = static_cast<Eigen::Index>(p.numbering.size);
  Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(n, n);
  std::set<std::pair<Index, Index>> coupled; // (row, column) of every coupled unknown pair
  for (const auto& c : p.cliques) {
    const auto m = static_cast<Eigen::Index>(c.size());
    const Eigen::MatrixXd K = random_block(Dim * m, rng);
    const Eigen::MatrixXd M = random_block(m, rng);
    const int a = static_cast<int>(rng() % Dim);
    assembler.add_block(c, K);
    assembler.add_component_block(c, a, M);
    for (Eigen::Index l = 0; l < m; ++l)
      for (int b = 0; b < Dim; ++b)
        for (Eigen::Index k = 0; k < m; ++k)
          for (int e = 0; e < Dim; ++e) {
            const Index row = p.numbering(c[static_cast<std::size_t>(k)], e);
            const Index col = p.numbering(c[static_cast<std::size_t>(l)], b);
            if (row < 0 || col < 0)
              continue;
            dense(row, col) += K(Dim * k + e, Dim * l + b);
            if (e == a && b == a)
              dense(row, col) += M(k, l);
            coupled.insert({row, col});
          }
  }
  for (Index d = 0; d < p.numbering.size; d += 3) {
    assembler.add_diagonal(d, 0.5 * static_cast<double>(d));
    dense(d, d) += 0.5 * static_cast<double>(d);
  }
  const talus::SparseMatrix& A = assembler.finish();
  // The structure holds exactly the coupled pairs: one entry per pair, no more.
  EXPECT_EQ(A.nonZeros(), static_cast<Eigen::Index>(coupled.size()));
  for (Eigen::Index j = 0; j < A.outerSize(); ++j)
    for (int e = A.outerIndexPtr()[j] + 1; e < A.outerIndexPtr()[j + 1]; ++e)
      ASSERT_LT(A.innerIndexPtr()[e - 1], A.innerIndexPtr()[e]) << "column " << j;
  // The same sums in the same order: equal to the last bit.
  EXPECT_EQ((Eigen::MatrixXd(A) - dense).cwiseAbs().maxCoeff(), 0.0);

  // A second build of the same cliques is recognised; the values start again from zero.
  build(assembler, p);
  EXPECT_TRUE(assembler.same_structure_as_before());
  EXPECT_EQ(Eigen::MatrixXd(assembler.finish()).cwiseAbs().maxCoeff(), 0.0);
  // Half the cliques leave pairs uncoupled: a different structure.
  Problem<Dim> fewer = p;
  fewer.cliques.resize(p.cliques.size() / 2);
  build(assembler, fewer);
  EXPECT_FALSE(assembler.same_structure_as_before());
}

} // namespace

TEST(LatticeAssembler, EqualsDenseSumIn2D) {
  for (std::uint32_t seed = 1; seed <= 5; ++seed)
    check_against_dense<2>(seed);
}

TEST(LatticeAssembler, EqualsDenseSumIn3D) {
  for (std::uint32_t seed = 1; seed <= 2; ++seed)
    check_against_dense<3>(seed);
}

TEST(LatticeAssembler, RefusesBlocksOutsideTheStructure) {
  const Grid<2> grid(talus::Vec<2>::Zero(), 1.0, {6, 6});
  std::vector<Index> every(static_cast<std::size_t>(grid.node_count()));
  for (std::size_t n = 0; n < every.size(); ++n)
    every[n] = static_cast<Index>(n);
  ActiveNodes<2> nodes;
  nodes.assign(grid, every);
  const auto id = [&](Index i, Index j) { return grid.node_id({i, j}); };
  Numbering<2> numbering;
  numbering.dof.assign(static_cast<std::size_t>(2 * grid.node_count()), -1);
  for (Index n = 0; n < grid.node_count(); ++n)
    for (int a = 0; a < 2; ++a)
      numbering.dof[static_cast<std::size_t>(2 * n + a)] = numbering.size++;
  // Two stencils of 2 x 2 nodes that share no node.
  const std::vector<Index> left = {id(0, 0), id(1, 0), id(0, 1), id(1, 1)};
  const std::vector<Index> right = {id(2, 0), id(3, 0), id(2, 1), id(3, 1)};
  LatticeAssembler<2> assembler;
  assembler.build(nodes, talus::NodeLayout(2), numbering.size, numbering, [&](auto&& f) {
    f(std::span<const Index>(left));
    f(std::span<const Index>(right));
  });
  // Nodes 1 and 2 are one lattice step apart, within the reach, but were never coupled.
  const std::vector<Index> across = {id(1, 0), id(2, 0)};
  EXPECT_THROW(assembler.add_block(across, Eigen::MatrixXd::Zero(4, 4)), std::logic_error);
  // Three steps apart: wider than any declared clique.
  const std::vector<Index> wide = {id(0, 0), id(3, 0)};
  EXPECT_THROW(assembler.add_block(wide, Eigen::MatrixXd::Zero(4, 4)), std::logic_error);
  EXPECT_THROW(assembler.add_block(left, Eigen::MatrixXd::Zero(4, 4)), std::invalid_argument);

  // A node whose two unknowns are not neighbours in the numbering.
  Numbering<2> scattered = numbering;
  scattered.dof[static_cast<std::size_t>(2 * id(0, 0) + 1)] = numbering.size;
  scattered.size = numbering.size + 1;
  EXPECT_THROW(assembler.build(nodes, talus::NodeLayout(2), scattered.size, scattered,
                               [&](auto&& f) { f(std::span<const Index>(left)); }),
               std::invalid_argument);
}
