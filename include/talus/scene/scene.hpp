#pragma once
// A Scene is everything a solver needs, built once from a validated CaseSpec: the grid, the
// material points generated from the bodies, the material models, node constraints, loads and
// probes. Building it is the last place a case can be rejected as bad input (exit 2).
#include "talus/core/particles.hpp"
#include "talus/grid/grid.hpp"
#include "talus/grid/node_conditions.hpp"
#include "talus/grid/surface_load.hpp"
#include "talus/material/material.hpp"
#include "talus/parallel/decomposition.hpp"
#include "talus/scene/pore_water.hpp"
#include "talus/spec/case_spec.hpp"

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
  /// The grid faces' conditions on a node (held components, reaction faces).
  FaceConditions<Dim> face_conditions;
  /// The prescribed-displacement boxes where they stand; the implicit solver moves them with
  /// the prescribed displacement every step (place_prescribed_boxes).
  PrescribedBoxes<Dim> prescribed_boxes;
  std::vector<SurfaceLoad<Dim>> surface_loads; ///< the tractions, per loaded point
  std::vector<Index> probe_particles;          ///< one particle per ProbeSpec, same order
  /// The water acting now: the case's at rest, or moving during a stage (the run sets it).
  PoreWater water;
  std::vector<std::string> probe_names;
  /// The split of the cells over the run's ranks: one rank owning everything (build_scene),
  /// until a distributed run partitions the scene. Each rank's scene then holds its own points
  /// only (parallel/migration.hpp), and a probe whose point lives on another rank has the
  /// particle -1.
  std::shared_ptr<const Decomposition<Dim>> decomposition;

  bool distributed() const { return decomposition && decomposition->comm().distributed(); }
};

/// Throws InputError (with the spec's locations) for a scene that cannot be built, e.g. a body
/// that yields no particle at the chosen resolution. Dim is the case's dimension.
template <int Dim> Scene<Dim> build_scene(const CaseSpec& spec);

/// Places scene.prescribed_boxes at the fraction `ramp` of their prescribed displacement.
template <int Dim> void place_prescribed_boxes(Scene<Dim>& scene, double ramp) {
  scene.prescribed_boxes.place(scene.grid, scene.spec.prescribed, ramp);
}

} // namespace talus
