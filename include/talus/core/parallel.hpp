#pragma once
// OpenMP loop that carries an exception out of the parallel region (OpenMP forbids throwing
// across it): the first exception any thread raises is re-thrown after the loop.
#include "talus/core/types.hpp"

#include <exception>
#include <mutex>

namespace talus {

/// Loops shorter than this run on the calling thread: waking threads costs more than it saves.
constexpr Index kParallelGrain = 256;

template <class Body> void parallel_for(Index n, Body&& body) {
  std::exception_ptr error;
  std::mutex error_mutex;
#pragma omp parallel for schedule(static) if (n >= kParallelGrain)
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

} // namespace talus
