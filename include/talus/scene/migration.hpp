#pragma once
// Points moving between the ranks of a distributed run, with everything they carry: every
// particle array (Particles::for_each_field), each material's per-point history, the tractions
// on their faces and the probes that follow them. Each rank keeps its points in ascending
// global id (the serial run's order), so a rank's sums run in the serial order.
#include "talus/parallel/decomposition.hpp"
#include "talus/scene/scene.hpp"

#include <functional>

namespace talus {

/// Turns a scene every rank built whole into this rank's share: numbers the points (global_id:
/// the serial index), partitions the cells that hold them (scene.decomposition) and keeps the
/// points this rank owns. Collective; does nothing in a serial run.
template <int Dim> void distribute_scene(Scene<Dim>& scene, const Communicator& comm);

struct MigrationCount {
  Index sent = 0;     ///< points this rank handed to others
  Index received = 0; ///< points it took in
};

/// Sends the points whose cell another rank owns to that rank. Collective.
template <int Dim> MigrationCount migrate_points(Scene<Dim>& scene);

/// Partitions the cells again when the ranks' shares of the points have drifted apart (the
/// largest above `threshold` times the mean) and moves the points to their new owners. The
/// decomposition is replaced: a solver takes it anew each step. Collective; returns the points
/// this rank handed to others (-1: no repartition).
template <int Dim> Index rebalance(Scene<Dim>& scene, double threshold);

/// Names the points a rank appended from `first_new` on (splitting: each a copy of its parent,
/// global id included) as the serial run numbers them: after all the points there were, in the
/// order of their parents' global ids. Collective; returns the number of new points over all
/// ranks.
template <int Dim> Index name_new_points(Scene<Dim>& scene, Index first_new);

/// Runs `work` with every point, and all it carries, on rank 0 (in the serial order: the scene
/// there is the serial run's), then sends the points back to their owners, bit for bit.
/// Collective; `work` runs on every rank (the others hold no point meanwhile).
template <int Dim> void with_points_on_root(Scene<Dim>& scene, const std::function<void()>& work);

/// Every rank's points, in global id order, on rank 0 (empty elsewhere), with their material's
/// plastic strain when `plastic_strain` is given (one value per point on return). Collective.
template <int Dim>
Particles<Dim> gather_points(const Scene<Dim>& scene, std::vector<double>* plastic_strain);

} // namespace talus
