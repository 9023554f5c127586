#pragma once
// A share of the material points: the contiguous range [begin, end) of particle indices one
// process assembles (its own points), with the share's index. The serial solver is one share
// holding every point; a later issue gives each MPI rank its own.
#include "talus/core/types.hpp"

namespace talus {

struct ParticleShare {
  int index = 0;
  Index begin = 0;
  Index end = 0;

  Index size() const { return end - begin; }
  bool contains(Index p) const { return p >= begin && p < end; }
};

} // namespace talus
