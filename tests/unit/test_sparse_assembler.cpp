// SparseAssembler (include/talus/linalg/sparse_assembler.hpp): a replayed pass gives the same
// matrix as a freshly recorded one, and a pass with a different number of contributions is
// refused.
#include "talus/linalg/sparse_assembler.hpp"

#include <gtest/gtest.h>

#include <random>
#include <stdexcept>

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

} // namespace

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
