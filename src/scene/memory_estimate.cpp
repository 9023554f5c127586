#include "talus/scene/memory_estimate.hpp"

#include "talus/scene/body_geometry.hpp"

#include "talus/grid/particle_grid_map.hpp"
#include "talus/linalg/linear_solver.hpp"
#include "talus/material/plastic_material.hpp"
#include "talus/material/plasticity/elastoplastic_response.hpp"
#include "talus/material/stress_tangent.hpp"
#include "talus/shape/shape_functions.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fmt/format.h>
#include <fstream>
#include <numbers>
#include <sstream>
#include <unistd.h>

namespace talus {

namespace {

// Every size below is the sizeof of the array element the code allocates (Particles, Scene,
// ParticleGridMap, the solvers, PlasticMaterial); tests/unit/test_memory_estimate.cpp compares
// the sum with the heap a small scene really takes.

/// The always-present per-point arrays of Particles (particles.hpp): five Dim-vectors (x, v,
/// half-size, x0, point load), mass, volume, volume0, F and stress (3x3 each), material, body.
constexpr double particle_core(int dims) {
  return 5 * dims * sizeof(double) + 3 * sizeof(double) + 2 * sizeof(Mat3) + 2 * sizeof(int);
}
/// build_scene: the lattice positions (Dim-vectors) and particles_of_material (Index).
constexpr double scene_build(int dims) {
  return dims * sizeof(double) + sizeof(Index);
}
/// PlasticMaterial: converged and trial history and F, and the return type of each point.
constexpr double kPlasticState = 2 * sizeof(PlasticHistory) + 2 * sizeof(Mat3) + sizeof(int);
/// Splitting: F0^-1 and the generation of each point.
constexpr double kSplitState = sizeof(Mat3) + sizeof(int);
/// A frame's largest field buffer (stress, 9 doubles per point) written by the results writer.
constexpr double kFrameBuffer = 9 * sizeof(double);
/// The implicit solver's trial state per point (implicit_solver_impl.hpp): trial F (Mat3), dF
/// (Dim x Dim), the stress and its tangent, det dF, F-bar's H (Dim x Dim), FBarCells' point
/// lists, and the tangent structure's stencil list.
constexpr double implicit_point(int dims) {
  return sizeof(Mat3) + 2 * dims * dims * sizeof(double) + sizeof(StressTangent) + sizeof(double) +
         5 * sizeof(Index) + sizeof(double);
}

/// Every array indexed by node is per active node (active_nodes.hpp); nothing is allocated per
/// node of the grid. Per active node, the map: its lattice id, its bin per stencil row (int32;
/// W^(Dim-1) rows) and the two buffers the nodes are dilated in; per bin (at most one per
/// active node): its node per stencil row, its first node's id and its offset.
double node_map(int rows) {
  return sizeof(Index) + rows * sizeof(std::int32_t) + 2 * sizeof(Index);
}
double bin_map(int rows) {
  return rows * sizeof(std::int32_t) + 2 * sizeof(Index);
}
/// Explicit solver: mass, four Dim-vectors (momentum, force, velocity, acceleration), the held
/// components and the reaction faces.
constexpr double node_explicit(int dims) {
  return sizeof(double) + 4 * dims * sizeof(double) + 1 + dims;
}
/// Implicit solver: node mass, prescribed region and reaction faces, Dim DOF numbers,
/// prescribed increments, external and internal forces per node, the ghost penalty's flags and
/// moduli, the owners of the nodes, and the lattice assembler's and F-bar's node slots.
constexpr double node_implicit(int dims) {
  return sizeof(double) + 4 + dims + dims * (sizeof(Index) + 3 * sizeof(double)) + 1 +
         sizeof(double) + 3 * sizeof(int) + sizeof(Index);
}
/// The sparse Cholesky / LU factor of a 3D grid's tangent: measured with CHOLMOD on the 3D
/// cantilever, 1.94 GB beyond the rest at 111.5k unknowns and growing like n^1.8 between 15.7k
/// and 111.5k (57 MB, 480 MB, 1.94 GB at 15.7k, 49k, 111.5k; nested dissection's n^(4/3) is
/// the asymptote, not what these sizes see). In entries of 12 bytes.
double factor_entries_3d(double unknowns) {
  return 1.94e9 / 12.0 * std::pow(unknowns / 111521.0, 1.8);
}
/// An iterative solve (CG with MueLu) holds the matrix about this many times: the assembler's,
/// the row-major copy, Tpetra's and MueLu's hierarchy (measured 3.7 on the 3D cantilever at 49k
/// and 111.5k unknowns).
constexpr double kIterativeMatrixCopies = 3.7;

/// std::vector grows by doubling when points are appended one by one: the capacity it ends
/// with is the next power of two.
double grown(double n) {
  return n < 1 ? 0 : std::exp2(std::ceil(std::log2(n)));
}

/// The body's area (2D) or volume (3D).
double measure(const BodySpec& b, int dimension) {
  switch (b.shape) {
  case BodyShape::Rectangle: {
    double product = 1;
    for (int d = 0; d < dimension; ++d)
      product *= b.max[d] - b.min[d];
    return product;
  }
  case BodyShape::Disc:
    return dimension == 3 ? 4.0 / 3.0 * std::numbers::pi * std::pow(b.radius, 3)
                          : std::numbers::pi * b.radius * b.radius;
  case BodyShape::Cylinder:
    return std::numbers::pi * b.radius * b.radius * (b.axis_end - b.axis_start).norm();
  case BodyShape::Polygon: {
    double twice = 0;
    const std::size_t n = b.vertices.size();
    for (std::size_t i = 0; i < n; ++i) {
      const Vec2& p = b.vertices[i];
      const Vec2& q = b.vertices[(i + 1) % n];
      twice += p.x() * q.y() - p.y() * q.x();
    }
    return 0.5 * std::abs(twice) * (dimension == 3 ? b.z_max - b.z_min : 1.0);
  }
  }
  return 0;
}

/// Lattice sites of spacing h / n over [lo, hi] as build_scene lays them out (cell-centred,
/// aligned with the grid), times the share of the bounding box the body covers.
double body_points(const BodySpec& b, const GridSpec& g, double& cells_in_box) {
  const int dims = g.dimension;
  Vec3 lo, hi;
  bounding_box(b, dims, lo, hi);
  const double h = g.cell_size;
  double box = 1;
  for (int d = 0; d < dims; ++d)
    box *= hi[d] - lo[d];
  const double fill = box > 0 ? std::min(1.0, measure(b, dims) / box) : 0.0;
  const auto sites = [&](double spacing, const Vec3& offset) {
    double count = 1;
    for (int d = 0; d < dims; ++d) {
      const double origin = g.origin[d] + spacing * offset[d];
      count *= std::max(0.0, std::ceil((hi[d] - origin) / spacing) -
                                 std::floor((lo[d] - origin) / spacing));
    }
    return count;
  };
  cells_in_box = sites(h, Vec3::Zero());
  const double per_cell = std::pow(b.particles_per_cell, dims);
  if (!b.refine)
    return fill * sites(h / b.particles_per_cell, b.placement.offset);
  // Refined: cells whose centre lies in a refine box take refine.particles_per_cell.
  double refined_cells = 0;
  for (const auto& r : b.refine->boxes) {
    double overlap = 1;
    for (int d = 0; d < dims; ++d)
      overlap *= std::max(0.0, std::min(hi[d], r.max[d]) - std::max(lo[d], r.min[d]));
    refined_cells += overlap / std::pow(h, dims);
  }
  refined_cells = std::min(refined_cells, cells_in_box);
  const double refined_per_cell = std::pow(b.refine->particles_per_cell, dims);
  return fill * ((cells_in_box - refined_cells) * per_cell + refined_cells * refined_per_cell);
}

/// A point's stencil in the map: its first node and W values and slopes per direction.
static_assert(sizeof(ParticleGridMap<3, CpGimpShape>::Stencil) ==
              3 * sizeof(Index) + 2 * 3 * CpGimpShape::kWidth * sizeof(double));
/// CPDI keeps a weight and a gradient on each of the W^Dim nodes.
static_assert(sizeof(ParticleGridMap<3, CpdiShape>::Stencil) ==
              3 * sizeof(Index) + 64 * 4 * sizeof(double));
std::size_t stencil_bytes(ShapeFunction shape, int dims) {
  const auto w = static_cast<std::size_t>(stencil_width(shape));
  const auto d = static_cast<std::size_t>(dims);
  if (shape == ShapeFunction::Cpdi)
    return d * sizeof(Index) + static_cast<std::size_t>(std::pow(w, d)) * (1 + d) * sizeof(double);
  return d * sizeof(Index) + 2 * d * w * sizeof(double);
}

bool any_implicit(const CaseSpec& spec) {
  if (spec.stages.empty())
    return spec.analysis != AnalysisType::Explicit || spec.strength_reduction.has_value();
  return std::any_of(spec.stages.begin(), spec.stages.end(),
                     [](const StageSpec& s) { return s.analysis != AnalysisType::Explicit; });
}

bool any_explicit(const CaseSpec& spec) {
  if (spec.stages.empty())
    return spec.analysis == AnalysisType::Explicit;
  return std::any_of(spec.stages.begin(), spec.stages.end(),
                     [](const StageSpec& s) { return s.analysis == AnalysisType::Explicit; });
}

} // namespace

std::string format_bytes(double bytes) {
  const char* units[] = {"B", "kB", "MB", "GB", "TB"};
  int u = 0;
  while (u < 4 && bytes >= 1000) {
    bytes /= 1000;
    ++u;
  }
  if (bytes >= 1e4)
    return fmt::format("{:.2g} {}", bytes, units[u]);
  return fmt::format("{:.3g} {}", bytes, units[u]);
}

std::string MemoryEstimate::describe() const {
  const std::string cells = cells_z > 1
                                ? fmt::format("{:.3g} x {:.3g} x {:.3g}", cells_x, cells_y, cells_z)
                                : fmt::format("{:.3g} x {:.3g}", cells_x, cells_y);
  return fmt::format("{} (grid of {} cells, {:.3g} active nodes: {}; {:.3g} material points: "
                     "{}{})",
                     format_bytes(total_bytes), cells, active_nodes, format_bytes(grid_bytes),
                     points, format_bytes(point_bytes),
                     matrix_bytes > 0 ? "; implicit matrix and its solver (factor or multigrid): " +
                                            format_bytes(matrix_bytes)
                                      : std::string());
}

MemoryEstimate estimate_memory(const CaseSpec& spec) {
  MemoryEstimate e;
  const GridSpec& g = spec.grid;
  const int dims = spec.dimension;
  e.cells_x = std::round(g.extent.x() / g.cell_size);
  e.cells_y = std::round(g.extent.y() / g.cell_size);
  if (dims == 3)
    e.cells_z = std::round(g.extent.z() / g.cell_size);
  const double ghosts = 1 + 2 * static_cast<double>(Grid<2>::kGhost);
  e.nodes = (e.cells_x + ghosts) * (e.cells_y + ghosts) * (dims == 3 ? e.cells_z + ghosts : 1.0);

  const bool implicit = any_implicit(spec);
  const bool explicit_stage = any_explicit(spec);
  const bool splitting = std::any_of(spec.bodies.begin(), spec.bodies.end(),
                                     [](const BodySpec& b) { return b.split.has_value(); });
  const bool apic = spec.solver.transfer == TransferScheme::Apic;
  const bool dynamic = spec.analysis == AnalysisType::ImplicitDynamic ||
                       std::any_of(spec.stages.begin(), spec.stages.end(), [](const StageSpec& s) {
                         return s.analysis == AnalysisType::ImplicitDynamic;
                       });

  double active = 0;
  double largest = -1;
  for (std::size_t i = 0; i < spec.bodies.size(); ++i) {
    const BodySpec& b = spec.bodies[i];
    double cells = 0;
    const double n = body_points(b, g, cells);
    e.body_points.push_back(n);
    e.points += n;
    // The nodes a body's points touch: its cells as a square (cubic) block plus the stencil's
    // ring (three nodes wide, four with the four-node stencils).
    const double side = std::pow(cells, 1.0 / dims);
    active += std::pow(side + std::max(3, stencil_width(spec.solver.shape)), dims);
    if (b.split)
      e.split_growth = std::max(e.split_growth, std::exp2(b.split->max_generations));
    if (n > largest) {
      largest = n;
      e.driver_body = static_cast<int>(i);
    }
  }
  e.active_nodes = std::min(active, e.nodes);

  // Per point: what every run has, then what the materials, the map and the solver add.
  double per_point_grown = particle_core(dims) + scene_build(dims) + (splitting ? kSplitState : 0) +
                           (spec.water ? sizeof(double) : 0);
  // The map per point: its stencil, first node id, bin, and place in the sorted bins (twice).
  double per_point = stencil_bytes(spec.solver.shape, dims) + 3 * sizeof(Index) +
                     sizeof(std::int32_t) + kFrameBuffer;
  if (explicit_stage && apic)
    per_point += dims * dims * sizeof(double) + dims * sizeof(double);
  if (implicit)
    per_point += implicit_point(dims) + (dynamic ? dims * sizeof(double) : 0);
  double plastic_points = 0;
  for (std::size_t i = 0; i < spec.bodies.size(); ++i) {
    const auto m = static_cast<std::size_t>(spec.bodies[i].material_index);
    if (m < spec.materials.size() && is_plastic(spec.materials[m].model))
      plastic_points += e.body_points[i];
  }
  e.point_bytes =
      grown(e.points) * per_point_grown + e.points * per_point + plastic_points * kPlasticState;

  const int rows = static_cast<int>(std::pow(stencil_width(spec.solver.shape), dims - 1));
  const double bins = std::min(e.points, e.active_nodes);
  e.grid_bytes = e.active_nodes * node_map(rows) + bins * bin_map(rows);
  if (explicit_stage)
    e.grid_bytes += e.active_nodes * node_explicit(dims);
  if (implicit) {
    e.grid_bytes += e.active_nodes * node_implicit(dims);
    // The tangent: each unknown couples with the unknowns of the nodes that share a point with
    // it (2W - 1 nodes per direction, W the stencil width; with F-bar or a consolidation's
    // pressure projection the nodes that share a cell's points, 2W + 1), Dim per node and a
    // pore pressure in a consolidation case; values and indices, held by
    // the assembler's matrix and by the linear solver's copy. The lattice assembler adds a
    // table of (2R + 1)^Dim ints per active node, R the widest coupling (lattice_assembler.hpp).
    // The sparse factor with nested dissection holds about 8 n log2(n) entries on a 2D mesh
    // (George 1973) and about FACTOR n^(4/3) on a 3D one (measured, see below).
    const int per_node = dims + (spec.consolidates() ? 1 : 0);
    const double dofs = per_node * e.active_nodes;
    const double w = stencil_width(spec.solver.shape);
    const double reach = spec.solver.f_bar || spec.consolidates() ? w : w - 1;
    const double coupled_nodes = std::pow(2 * reach + 1, dims);
    const double row = per_node * coupled_nodes;
    const double entry = sizeof(double) + sizeof(int);
    const double factor_entries =
        dims == 2 ? 8 * dofs * std::log2(std::max(2.0, dofs)) : factor_entries_3d(dofs);
    const double tables = e.active_nodes * coupled_nodes * sizeof(int);
    // The backend the solver will take (the case's, or the automatic choice).
    const bool symmetric = symmetric_implicit_tangent(spec);
    LinearSolverKind kind =
        spec.consolidates()
            ? LinearSolverKind::Umfpack // the solver's choice for u-p
            : automatic_linear_solver(symmetric, dims, static_cast<long long>(dofs));
    if (!spec.solver.linear_solver.empty())
      parse_linear_solver_kind(spec.solver.linear_solver, kind);
    const bool iterative =
        kind == LinearSolverKind::TrilinosCg || kind == LinearSolverKind::TrilinosGmres ||
        kind == LinearSolverKind::EigenCg || kind == LinearSolverKind::EigenBicgstab;
    e.matrix_bytes = iterative ? dofs * row * entry * kIterativeMatrixCopies + tables
                               : dofs * row * entry * 2 + factor_entries * entry + tables;
  }
  e.total_bytes = e.grid_bytes + e.point_bytes + e.matrix_bytes;

  // Which key to name: a body's own point density when its points dominate and it asks for more
  // than one point per direction, otherwise the cell size (which drives both).
  e.driver_key = "grid.cell_size";
  if (e.driver_body >= 0 && e.point_bytes > e.grid_bytes + e.matrix_bytes) {
    const BodySpec& b = spec.bodies[static_cast<std::size_t>(e.driver_body)];
    const std::string body = fmt::format("bodies[{}]", e.driver_body);
    if (b.refine && b.refine->particles_per_cell > b.particles_per_cell)
      e.driver_key = body + ".refine.particles_per_cell";
    else if (b.particles_per_cell > 1)
      e.driver_key = body + ".particles_per_cell";
  } else {
    e.driver_body = -1;
  }
  return e;
}

MachineMemory machine_memory() {
  MachineMemory m;
  std::ifstream meminfo("/proc/meminfo");
  std::string line;
  while (std::getline(meminfo, line)) {
    std::istringstream in(line);
    std::string key;
    double kib = 0;
    in >> key >> kib;
    if (key == "MemTotal:")
      m.total_bytes = kib * 1024;
    else if (key == "MemAvailable:")
      m.available_bytes = kib * 1024;
  }
  m.source = "MemTotal of /proc/meminfo";
  if (m.total_bytes <= 0) {
    const long pages = sysconf(_SC_PHYS_PAGES);
    const long page = sysconf(_SC_PAGE_SIZE);
    m.total_bytes = static_cast<double>(pages) * static_cast<double>(page);
    m.source = "sysconf(_SC_PHYS_PAGES)";
  }
  if (m.available_bytes <= 0)
    m.available_bytes = m.total_bytes;
  // A container's memory limit (cgroup v2, then v1) is what the process can really have.
  for (const char* file :
       {"/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory/memory.limit_in_bytes"}) {
    std::ifstream in(file);
    double limit = 0;
    if (in >> limit && limit > 0 && limit < m.total_bytes) {
      m.total_bytes = limit;
      m.available_bytes = std::min(m.available_bytes, limit);
      m.source = std::string("the memory limit in ") + file;
      break;
    }
  }
  return m;
}

} // namespace talus
