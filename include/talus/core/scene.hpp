#pragma once
// A Scene is everything a solver needs, built once from a validated CaseSpec: the grid, the
// material points generated from the bodies, the material models, node constraints, loads and
// probes. Building it is the last place a case can be rejected as bad input (exit 2).
#include "talus/core/particles.hpp"
#include "talus/grid/grid.hpp"
#include "talus/grid/surface_load.hpp"
#include "talus/io/case_spec.hpp"
#include "talus/material/material.hpp"

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace talus {

/// Reaction force on each grid face (Face order), N (per unit thickness in 2D; z = 0 there).
using FaceReactions = std::array<Vec3, kMaxFaces>;

template <int Dim> struct Scene {
  CaseSpec spec;
  Grid<Dim> grid;
  Particles<Dim> particles;
  std::vector<std::unique_ptr<Material>> materials;
  std::vector<std::vector<Index>> particles_of_material; ///< batches for the material update
  /// Per node, bit d set: velocity component d is held at zero (fixed or roller face).
  std::vector<std::uint8_t> constrained;
  /// Per node and velocity component (index Dim n + d), the face whose condition holds that
  /// component (-1 if none): the face that receives its reaction. At a corner each component
  /// goes to the face that constrains it, preferring the face normal to it.
  std::vector<std::int8_t> component_face;
  /// Per node, the index of the PrescribedSpec whose box holds it (-1 if none). The boxes follow
  /// their prescribed displacement in whole cells (a rigid footing carries its box down with
  /// it), so the implicit solver relocates them every step (locate_prescribed_nodes).
  std::vector<std::int32_t> node_prescribed;
  std::vector<SurfaceLoad<Dim>> surface_loads; ///< the tractions, per loaded point
  std::vector<Index> probe_particles;          ///< one particle per ProbeSpec, same order
  std::vector<std::string> probe_names;
};

/// Throws InputError (with the spec's locations) for a scene that cannot be built, e.g. a body
/// that yields no particle at the chosen resolution. Dim is the case's dimension.
template <int Dim> Scene<Dim> build_scene(const CaseSpec& spec);

/// Fills scene.node_prescribed with the nodes inside each prescribed box shifted by the
/// fraction `ramp` of its prescribed displacement (given components only), rounded to whole
/// cells.
template <int Dim> void locate_prescribed_nodes(Scene<Dim>& scene, double ramp);

} // namespace talus
