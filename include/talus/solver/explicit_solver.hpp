#pragma once
// Explicit dynamic MPM (USL, USF, MUSL) with a FLIP/PIC blend. One step:
//   locate points -> active grid -> P2G (gather) -> grid update + constraints -> G2P
//   -> F, volume and stress update (order per scheme).
// The particle-to-grid transfer is written as a gather: every active node sums over the
// particles of the neighbouring bins in a fixed order. No two threads write the same node, so
// the result is bitwise identical for any thread count.
#include "talus/scene/scene.hpp"
#include "talus/solver/energies.hpp"
#include "talus/solver/state_guard.hpp"

#include <array>
#include <memory>
#include <optional>

namespace talus {

class ExplicitSolver {
public:
  virtual ~ExplicitSolver() = default;
  /// Advances by dt; throws NumericalError on a particle that leaves the grid or a material
  /// that cannot be evaluated.
  virtual void step(double dt) = 0;
  /// Largest stable step for the CFL number: cfl * h / max_p (c_p + |v_p|).
  virtual double stable_dt(double cfl) const = 0;
  virtual Energies energies() const = 0;
  /// Reaction force on each grid face from the last step (sum over constrained nodes), N.
  virtual FaceReactions reactions() const = 0;
  virtual Index active_nodes() const = 0;
  /// The state guard's look at the grid of the last step: the first active node whose
  /// velocity or acceleration is not finite.
  virtual std::optional<StateViolation> grid_violation() const = 0;
  /// The scene's points were added to (splitting, core/splitting.hpp) between steps: resizes
  /// whatever the solver keeps per point.
  virtual void particles_changed() = 0;
};

/// Picks the shape-function instantiation once, for the whole run. The points' stresses are
/// evaluated from their F first, unless `stress_current` (a stage resumed from a checkpoint).
template <int Dim>
std::unique_ptr<ExplicitSolver> make_explicit_solver(Scene<Dim>& scene,
                                                     bool stress_current = false);

} // namespace talus
