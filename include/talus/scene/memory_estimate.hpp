#pragma once
// What a case will allocate, estimated from its CaseSpec alone before anything is allocated:
// the per-node arrays of the nodes the material reaches, the material points each body generates
// (area / spacing^2, refine boxes included) with the per-point arrays of the particles, the
// material state, the particle-grid map and the solver, and for the implicit analyses the sparse
// matrix and its factor. The case reader refuses a case whose estimate exceeds the machine's
// memory, at the key that drives it (docs/case-format.md, "Memory"). Counts are doubles: a grid of
// 1e15 cells per axis must not wrap around in an integer.
#include "talus/spec/case_spec.hpp"

#include <string>
#include <vector>

namespace talus {

struct MemoryEstimate {
  double cells_x = 0, cells_y = 0, cells_z = 1; ///< grid cells per axis (cells_z 1 in 2D)
  double nodes = 0;                             ///< grid nodes, ghost layers included
  double active_nodes = 0;         ///< nodes touched by the points (implicit unknowns / 2)
  std::vector<double> body_points; ///< initial material points of each body
  double points = 0;               ///< all bodies
  double grid_bytes = 0;           ///< per-active-node arrays (map, solver)
  double point_bytes = 0;          ///< per-point arrays (particles, materials, map, solver)
  double matrix_bytes = 0;         ///< implicit analyses: tangent matrix, factor or multigrid
  double total_bytes = 0;
  /// Splitting can multiply a body's points by up to 2^max_generations while the run goes on;
  /// this is the largest such factor (1 without splitting). Not part of total_bytes.
  double split_growth = 1;
  /// The key whose value drives the estimate: "grid.cell_size" when the grid or the points of a
  /// body with the default density dominate, "bodies[i].particles_per_cell" (or
  /// "bodies[i].refine.particles_per_cell") when a body's own point density does.
  std::string driver_key;
  int driver_body = -1; ///< the body whose points dominate, or -1 when the grid does

  /// "1.2 GB (grid 4.1e6 nodes 410 MB, 2.0e6 points 780 MB, matrix 0 B)"
  std::string describe() const;
};

MemoryEstimate estimate_memory(const CaseSpec& spec);

/// The machine's memory as the estimate is compared with it.
struct MachineMemory {
  double total_bytes = 0;     ///< MemTotal of /proc/meminfo, or the cgroup limit if lower
  double available_bytes = 0; ///< MemAvailable of /proc/meminfo (what can be had now)
  std::string source;         ///< where total_bytes came from
};
MachineMemory machine_memory();

/// "1.5 GB", "812 MB", "3.2e+06 TB"
std::string format_bytes(double bytes);

} // namespace talus
