#pragma once
// OpenMP loops that carry an exception out of the parallel region (OpenMP forbids throwing
// across it: the first exception any thread raises is re-thrown after the loop), and
// reductions whose result does not depend on the number of threads.
#include "talus/core/types.hpp"

#include <algorithm>
#include <exception>
#include <mutex>
#include <vector>

namespace talus {

/// Loops shorter than this run on the calling thread: waking threads costs more than it saves.
constexpr Index kParallelGrain = 256;

/// body(i) for i in [0, n); on one thread when n < grain.
template <class Body> void parallel_for(Index n, Body&& body, Index grain = kParallelGrain) {
  std::exception_ptr error;
  std::mutex error_mutex;
#pragma omp parallel for schedule(static) if (n >= grain)
  for (Index i = 0; i < n; ++i) {
    try {
      body(i);
    } catch (...) {
      const std::lock_guard<std::mutex> lock(error_mutex);
      if (!error)
        error = std::current_exception();
    }
  }
  if (error)
    std::rethrow_exception(error);
}

/// Reductions cut [0, n) into blocks of this fixed length, whatever the thread count: each
/// block is reduced in index order and the blocks' results are combined in block order, so a
/// floating-point sum has the same rounding on one thread as on many.
constexpr Index kReductionBlock = 2048;

/// fold(T& acc, Index begin, Index end) reduces [begin, end) into acc (which starts as `zero`);
/// combine(T& acc, const T& block) adds a block's result. Returns the reduction of [0, n).
template <class T, class Fold, class Combine>
T parallel_reduce(Index n, const T& zero, Fold&& fold, Combine&& combine) {
  const Index blocks = (n + kReductionBlock - 1) / kReductionBlock;
  if (blocks <= 1) {
    T acc = zero;
    fold(acc, Index{0}, n);
    return acc;
  }
  std::vector<T> partial(static_cast<std::size_t>(blocks), zero);
  parallel_for(
      blocks,
      [&](Index b) {
        fold(partial[static_cast<std::size_t>(b)], b * kReductionBlock,
             std::min(n, (b + 1) * kReductionBlock));
      },
      2); // a block is already worth a thread
  T acc = partial.front();
  for (std::size_t b = 1; b < partial.size(); ++b)
    combine(acc, partial[b]);
  return acc;
}

/// sum over i of term(i), deterministic (blocks as in parallel_reduce).
template <class Term> double parallel_sum(Index n, Term&& term) {
  return parallel_reduce(
      n, 0.0,
      [&](double& acc, Index begin, Index end) {
        for (Index i = begin; i < end; ++i)
          acc += term(i);
      },
      [](double& acc, double block) { acc += block; });
}

/// The lowest i in [0, n) for which bad(i) holds, or -1.
template <class Pred> Index parallel_find_first(Index n, Pred&& bad) {
  const Index found = parallel_reduce(
      n, n,
      [&](Index& first, Index begin, Index end) {
        for (Index i = begin; i < end; ++i)
          if (bad(i)) {
            first = i;
            return;
          }
      },
      [](Index& first, Index block) { first = std::min(first, block); });
  return found < n ? found : -1;
}

} // namespace talus
