#pragma once
// `talus fos --refine N`: the factor of safety of one case on a sequence of grids, h, h/2, ...,
// h/2^(N-1) (the case's cell size first), to show whether it converges and how fast. Each
// finer search brackets near the coarser answer, and may step down from it (FosOptions::floor),
// so it needs fewer trials than a search over the case's whole range. From the last three
// levels: the observed order of convergence and the Richardson extrapolation to h = 0.
#include "talus/solver/strength_reduction.hpp"

#include <filesystem>
#include <optional>
#include <vector>

namespace talus {

struct FosLevel {
  double cell_size = 0;
  FosRunResult search; ///< in <out>/h<cell size>/
};

struct FosRefinement {
  std::vector<FosLevel> levels; ///< coarse to fine; ends early at a level with no bracket
  /// p = log2(|F(4h) - F(2h)| / |F(2h) - F(h)|) of the last three levels, when they are
  /// bracketed and the differences are not both within the search tolerance.
  std::optional<double> observed_order;
  /// F(h) + (F(h) - F(2h)) / (2^p - 1) with the observed order (0.5 <= p <= 4 only).
  std::optional<double> extrapolated;
  std::string message; ///< what the sequence shows, in words
  int exit_code = 0;   ///< 0 every level bracketed, 3 one was not, 1 interrupted
};

/// The first and the later levels' search ranges: level k > 0 starts at the coarser bracket
/// widened by `margin` (4 tolerances) on both sides, and may step down to half the coarser
/// factor. Writes refinement.csv, refinement.json and refinement.png (the factor against h
/// with each level's bracket) into options.out_dir.
FosRefinement refine_factor_of_safety(const CaseSpec& spec, const FosOptions& options, int levels);

} // namespace talus
