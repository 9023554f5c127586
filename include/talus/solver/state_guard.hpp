#pragma once
// The stepper's state guard: a run either gives bounded, physical numbers or stops with a
// reason, never NaN garbage. After every step one read-only pass (no allocation) looks for a
// value that is not finite in the grid or particle state, or a point whose det F is not
// positive (inverted or collapsed); with a fixed explicit time step the Courant number of
// every point is checked before the step. A finding names the field, the particle or node and
// where it sits; the stepper turns it into a NumericalError (exit 3).
#include "talus/core/errors.hpp"
#include "talus/core/particles.hpp"
#include "talus/grid/active_nodes.hpp"
#include "talus/scene/scene.hpp"

#include <optional>
#include <span>
#include <string>

namespace talus {

/// The guard's stop (exit 3). The state it found is not written: every frame on disk was
/// written after the guard passed its step, so the frames already written are the good ones.
class StateGuardError : public NumericalError {
public:
  using NumericalError::NumericalError;
};

struct StateViolation {
  std::string field;      ///< e.g. "velocity", "det F", "grid acceleration", "Courant number"
  bool on_node = false;   ///< a grid node, otherwise a particle
  Index index = -1;       ///< particle index (at this step) or grid node id
  Vec3 position{0, 0, 0}; ///< the particle's initial position, or the node's (z = 0 in 2D)
  int dimension = 2;      ///< how many components of position to print
  double value = 0;       ///< the offending value (the first non-finite component)
  std::string condition;  ///< what was violated, e.g. "is not finite", "<= 0"
  /// "det F = -0.45 <= 0 at particle 17 (initial position (0.1, 0.2))".
  std::string describe() const;
};

/// det F below which a point counts as collapsed. The midpoint F update never inverts a point
/// (each increment (I - dt L/2)^-1 (I + dt L/2) has det > 0 while the Courant number is below
/// 1), so a body driven through itself shrinks det F geometrically towards 0 instead of
/// crossing it; the guard must catch that too. A point at 1e-4 of its volume spans a hundredth
/// of its spacing per axis, far below anything the grid resolves, and no material of Talus
/// (soils, metals, rubber) compacts that far.
inline constexpr double kCollapsedVolumeRatio = 1e-4;

/// The lowest-index particle with a non-finite position, velocity, F or stress, or det F below
/// kCollapsedVolumeRatio (<= 0: inverted).
/// Particles are named with their initial position, which survives re-indexing (splitting).
template <int Dim>
std::optional<StateViolation> find_particle_violation(const Particles<Dim>& particles);

/// The first active node whose value in `field` (one entry per active node) is not finite.
template <int Dim>
std::optional<StateViolation> find_node_violation(const ActiveNodes<Dim>& nodes,
                                                  std::span<const Vec<Dim>> field,
                                                  const char* field_name);

/// With a fixed explicit step dt: the point with the largest Courant number
/// dt (c_p + |v_p|) / h when that number exceeds 1, the limit the case reader enforces at t = 0.
template <int Dim>
std::optional<StateViolation> find_courant_violation(const Scene<Dim>& scene, double dt);

} // namespace talus
