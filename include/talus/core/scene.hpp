#pragma once
// A Scene is everything a solver needs, built once from a validated CaseSpec: the grid, the
// material points generated from the bodies, the material models, node constraints, loads and
// probes. Building it is the last place a case can be rejected as bad input (exit 2).
#include "talus/core/particles.hpp"
#include "talus/grid/grid.hpp"
#include "talus/io/case_spec.hpp"
#include "talus/material/material.hpp"

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace talus {

/// Which grid face a constrained node belongs to, for reaction sums.
enum Face : int { kXMin = 0, kXMax = 1, kYMin = 2, kYMax = 3, kFaceCount = 4 };
const char* face_name(int face);

template <int Dim> struct Scene {
  CaseSpec spec;
  Grid<Dim> grid;
  Particles<Dim> particles;
  std::vector<std::unique_ptr<Material>> materials;
  std::vector<std::vector<Index>> particles_of_material; ///< batches for the material update
  /// Per node, bit d set: velocity component d is held at zero (fixed or roller face).
  std::vector<std::uint8_t> constrained;
  /// Per node, the face it belongs to (-1 if none); corners count for the x face.
  std::vector<std::int8_t> node_face;
  std::vector<Index> probe_particles; ///< one particle per ProbeSpec, same order
  std::vector<std::string> probe_names;
};

/// Throws InputError (with the spec's locations) for a scene that cannot be built, e.g. a body
/// that yields no particle at the chosen resolution.
Scene<2> build_scene(const CaseSpec& spec);

} // namespace talus
