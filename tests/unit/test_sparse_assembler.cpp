// SparseAssembler (include/talus/linalg/sparse_assembler.hpp): a replayed pass gives the same
// matrix as a freshly recorded one, a dense block adds exactly what its entries would, and a
// pass with a different number of contributions, a block of the wrong size or a DOF outside
// the matrix is refused.
#include "talus/linalg/sparse_assembler.hpp"

#include <gtest/gtest.h>

#include <random>
#include <stdexcept>
#include <vector>

using talus::Index;
using talus::SparseAssembler;

namespace {

// A fixed stream of contributions with duplicates (as from overlapping element stencils), with
// values drawn from `rng`.
void stream(SparseAssembler& a, std::mt19937& rng) {
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  for (Index e = 0; e < 20; ++e)
    for (Index i = e; i < e + 3; ++i)
      for (Index j = e; j < e + 3; ++j)
        a.add(i, j, value(rng));
}

// Element blocks over overlapping DOF lists, some DOFs negative (no unknown), added as blocks
// or, when `as_entries`, entry by entry in the block's (column-major) order.
void block_stream(SparseAssembler& a, std::mt19937& rng, bool as_entries) {
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  for (Index e = 0; e < 20; ++e) {
    const std::vector<Index> dofs = {e, e + 1, e % 3 == 0 ? -1 : e + 2, e + 3};
    Eigen::MatrixXd block(4, 4);
    for (Eigen::Index k = 0; k < block.size(); ++k)
      block.data()[k] = value(rng);
    if (!as_entries) {
      a.add_block(dofs, block);
      continue;
    }
    for (std::size_t j = 0; j < dofs.size(); ++j)
      for (std::size_t i = 0; i < dofs.size(); ++i)
        if (dofs[i] >= 0 && dofs[j] >= 0)
          a.add(dofs[i], dofs[j],
                block(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)));
  }
}

} // namespace

TEST(SparseAssembler, BlocksEqualTheirEntries) {
  SparseAssembler blocks, entries;
  for (int pass = 0; pass < 3; ++pass) { // one recording, then replays
    std::mt19937 values(10 + pass), values_copy(10 + pass);
    blocks.begin(23, pass == 0);
    block_stream(blocks, values, false);
    const talus::SparseMatrix A = blocks.finish();
    EXPECT_EQ(blocks.recorded(), pass == 0);
    entries.begin(23, pass == 0);
    block_stream(entries, values_copy, true);
    const talus::SparseMatrix B = entries.finish();
    ASSERT_EQ(A.nonZeros(), B.nonZeros());
    // The same sums in the same order: bitwise equal.
    EXPECT_EQ((talus::SparseMatrix(A - B)).cwiseAbs().sum(), 0.0);
  }
}

TEST(SparseAssembler, RefusesAWrongBlockOrALongerReplay) {
  SparseAssembler a;
  std::mt19937 rng(5);
  a.begin(23, true);
  const std::vector<Index> three = {0, 1, 2};
  EXPECT_THROW(a.add_block(three, Eigen::MatrixXd::Zero(2, 2)), std::invalid_argument);
  block_stream(a, rng, false);
  a.finish();
  a.begin(23, false);
  block_stream(a, rng, false);
  EXPECT_THROW(a.add_block(three, Eigen::MatrixXd::Zero(3, 3)), std::logic_error);
}

TEST(SparseAssembler, RefusesADofOutsideTheMatrix) {
  SparseAssembler a;
  a.begin(4, true);
  const std::vector<Index> dofs = {0, 4};
  EXPECT_THROW(a.add_block(dofs, Eigen::MatrixXd::Zero(2, 2)), std::out_of_range);
  EXPECT_THROW(a.add(4, 0, 1.0), std::out_of_range);
}

TEST(SparseAssembler, ReplayEqualsRecording) {
  SparseAssembler replayed, fresh;
  std::mt19937 rng(1), rng_copy(1);
  replayed.begin(22, true);
  stream(replayed, rng);
  replayed.finish();
  EXPECT_TRUE(replayed.recorded());
  for (int pass = 0; pass < 3; ++pass) {
    std::mt19937 values(100 + pass), values_copy(100 + pass);
    replayed.begin(22, false);
    stream(replayed, values);
    const talus::SparseMatrix A = replayed.finish();
    EXPECT_FALSE(replayed.recorded());
    fresh.begin(22, true);
    stream(fresh, values_copy);
    const talus::SparseMatrix B = fresh.finish();
    EXPECT_EQ(A.nonZeros(), B.nonZeros());
    // Same sums in the same order: bitwise equal.
    EXPECT_EQ((talus::SparseMatrix(A - B)).cwiseAbs().sum(), 0.0);
  }
}

TEST(SparseAssembler, RefusesAChangedStream) {
  SparseAssembler a;
  std::mt19937 rng(3);
  a.begin(22, true);
  stream(a, rng);
  a.finish();
  a.begin(22, false);
  a.add(0, 0, 1.0);
  EXPECT_THROW(a.finish(), std::logic_error);
}
