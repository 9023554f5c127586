#pragma once
// Pre-run adaptive discretisation (`talus adapt`, the reference talk's untested idea):
//   1. a pre-run of the case as written (the coarse discretisation);
//   2. mark, per body, the grid cells of the initial lattice whose points end the pre-run with
//      an accumulated plastic strain above `plastic_strain` or a voxel aspect ratio (long to
//      short singular value of F diag(h0)) above `aspect_ratio`, plus `buffer_cells` around
//      them (the action moves while it grows);
//   3. regenerate the bodies with `factor` times their points per direction in the marked
//      cells (bodies[].refine); the grid is one uniform structured grid, so it stays as it is;
//   4. run the adapted case in full.
// The marks use each point's initial position x0, which children of a split inherit, so a
// pre-run with splitting marks the same cells. With `benchmark`, a uniform fine run (factor
// times the points everywhere) is added and the coarse pre-run and the adapted run are
// compared with it on the final material extent (front and top of the deformed voxels) and
// wall time.
#include "talus/solver/run.hpp"

#include <filesystem>
#include <string>
#include <vector>

namespace talus {

struct AdaptOptions {
  std::filesystem::path out_dir; ///< empty: results/<case name>_adapt
  bool force = false;            ///< replace the results of an earlier adapt in out_dir
  int threads = 0;
  bool progress = true;
  int factor = 2;              ///< points per direction in marked cells, times the body's
  double plastic_strain = 0.1; ///< mark threshold on the accumulated plastic strain
  double aspect_ratio = 2.0;   ///< mark threshold on the voxel aspect ratio
  int buffer_cells = 1;        ///< cells added around the marked ones
  bool benchmark = false;      ///< add the uniform fine run and the comparison
};

/// One run of the workflow and what it is judged by.
struct AdaptRun {
  std::string label; ///< coarse (the pre-run), adapted, fine
  RunResult result;
  Index particles_initial = 0;
  double front = 0; ///< m, largest x of a deformed voxel corner at the end
  double top = 0;   ///< m, largest y of a deformed voxel corner at the end
};

struct AdaptReport {
  Index marked_cells = 0;             ///< after the buffer, over all bodies
  Index body_cells = 0;               ///< cells holding points of a body at t = 0
  std::vector<std::string> overrides; ///< the adapted case: the case file with these --set
  std::vector<AdaptRun> runs;         ///< coarse, adapted[, fine]
};

/// Runs the workflow; results under out_dir/{coarse,adapted,fine}, the report in
/// out_dir/adapt.md. Throws InputError for a bad case or options.
AdaptReport adapt_case(const std::string& case_file, const std::vector<std::string>& overrides,
                       const AdaptOptions& options);

/// The comparison table (markdown) of the report's runs.
std::string adapt_table(const AdaptReport& report);

} // namespace talus
