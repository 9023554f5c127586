#pragma once
// The evolving part of a Scene in a checkpoint: every allocated particle array (bitwise), each
// material's per-point history, the tractions' loaded points (splitting moves them) and the
// probes. The rest of a Scene (grid, materials' parameters, conditions) is rebuilt from the
// case, which a resume checks is the one the run started with.
#include "talus/io/checkpoint_file.hpp"
#include "talus/scene/scene.hpp"

namespace talus {

template <int Dim> void save_scene_state(const Scene<Dim>& scene, CheckpointWriter& out);

/// Overwrites the evolving state of `scene` (built from the same case) with the checkpoint's.
/// Throws std::runtime_error when the checkpoint does not fit the scene (another dimension,
/// other materials).
template <int Dim> void restore_scene_state(const CheckpointReader& in, Scene<Dim>& scene);

} // namespace talus
