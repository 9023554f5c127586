#pragma once
// Stable least-significant-digit radix sort of items by a non-negative integer key: linear in
// the number of items per 11-bit digit of the largest key (three passes for a lattice of eight
// million nodes). The particle-grid map sorts every step's points by their stencil's first
// node with it, which a comparison sort would make the slowest part of the map's update.
#include "talus/core/types.hpp"

#include <algorithm>
#include <array>
#include <vector>

namespace talus {

/// Reorders `items` stably by key(item) >= 0; `scratch` is working storage kept by the caller
/// so that repeated sorts do not allocate.
template <class Key>
void radix_sort_by(std::vector<Index>& items, Key&& key, std::vector<Index>& scratch) {
  constexpr int kBits = 11;
  constexpr Index kBuckets = Index{1} << kBits;
  Index largest = 0;
  for (const Index item : items)
    largest = std::max(largest, key(item));
  scratch.resize(items.size());
  std::array<Index, kBuckets + 1> start{};
  for (int shift = 0; shift == 0 || (largest >> shift) > 0; shift += kBits) {
    start.fill(0);
    for (const Index item : items)
      ++start[static_cast<std::size_t>(((key(item) >> shift) & (kBuckets - 1)) + 1)];
    for (std::size_t b = 1; b < start.size(); ++b)
      start[b] += start[b - 1];
    for (const Index item : items)
      scratch[static_cast<std::size_t>(
          start[static_cast<std::size_t>((key(item) >> shift) & (kBuckets - 1))]++)] = item;
    items.swap(scratch);
  }
}

} // namespace talus
