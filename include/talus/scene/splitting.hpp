#pragma once
// Material-point splitting (Andersen 2013, the reference talk): a point whose voxel has become
// too distorted is replaced, between two steps, by two points that share its state.
//
// F^split = F F0^-1 measures the deformation since the point was made (F0: its F then), so it
// starts at I and evolves like F without code of its own. A point splits when
//     F^split_11 or F^split_22 > alpha  (stretch),   < beta  (compression),
//     |F^split_12| or |F^split_21| > gamma            (shear),
// unless it already has max_generations splits in its ancestry or a child would be shorter
// than min_size across the cut.
//
// The split cuts the point's reference voxel (half-sizes half_size0 about x0) in two halves
// along one reference axis; F maps them onto the two halves of the deformed voxel. The axis is
// the one whose deformed edge, |F e_d| 2 h_d, is the longer: for the talk's six modes from a
// square voxel this is the stretched axis (stretch), the axis that was not compressed
// (compression) and the axis whose edge was sheared (F12 > gamma: y, F21 > gamma: x), and for
// a voxel made by earlier splits it halves the longest edge, which is what keeps the aspect
// ratio bounded. The children
//   * sit at the centroids of the two halves: x +- F (h_d / 2) e_d, x0 +- (h_d / 2) e_d;
//   * halve mass, volume, reference volume, point loads and the GIMP half-width along d;
//   * share velocity, APIC affine velocity, Newmark acceleration, stress, F and the material's
//     history; restart F^split at I (F0 = F) and count one more generation.
// Mass, volume and linear momentum are conserved exactly (halving is exact in binary), the
// first mass moment to round-off, and the kinetic energy exactly (shared velocity).
#include "talus/scene/scene.hpp"

#include <cstdint>

namespace talus {

enum class SplitMode : std::uint8_t { None, Stretch, Compression, Shear };

/// Which criterion F^split (the block of the grid's axes) meets, stretch before compression
/// before shear, or None: any diagonal term above alpha or below beta, any off-diagonal one
/// beyond gamma in magnitude.
template <int Dim> SplitMode split_mode(const Mat<Dim>& F_split, const SplitSpec& spec);

/// The reference axis (0: x, 1: y, 2: z) whose deformed voxel edge |F e_d| h_d is the longest
/// (the first on a tie): the axis a split cuts in half.
template <int Dim> int split_axis(const Mat<Dim>& F, const Vec<Dim>& half_size0);

/// Whether any body of the case splits its points.
bool splitting_requested(const CaseSpec& spec);

/// Allocates the particles' splitting block (F0^-1 = I, generation 0) when a body splits;
/// otherwise leaves it empty, and split_material_points() then does nothing.
template <int Dim> void enable_splitting(Scene<Dim>& scene);

/// Splits point p along reference axis `axis`: p becomes the child on the negative side, the
/// child on the positive side is appended. Particles only: the caller updates the materials'
/// history, the batches and the loads (split_material_points does all of it).
template <int Dim> Index split_point(Particles<Dim>& particles, Index p, int axis);

/// Splits every point whose body has a split block and whose F^split meets the criterion;
/// children are checked at the next call. Updates the materials' history, the material
/// batches, the tractions (a loaded face stays on the child that holds it) and returns the
/// number of splits. Solvers must be told (particles_changed) when it is non-zero.
template <int Dim> Index split_material_points(Scene<Dim>& scene);

} // namespace talus
