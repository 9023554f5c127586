#pragma once
// Internal to the scene (src/scene/): loads that reach no material are input errors, found once
// the points exist. A prescribed box that holds no node of the material's cells carries no load
// (a footing placed above the surface completes with a zero reaction), and a point load acts on
// the point nearest to it, which must be close to where the case puts it.
#include "talus/scene/scene.hpp"

namespace talus {

/// Throws InputError at the load's key when a prescribed box, swept along its whole prescribed
/// displacement, holds no corner of a cell that holds points, or when a point load lies farther
/// than one cell from every point.
template <int Dim> void check_loads_reach_material(const Scene<Dim>& scene);

} // namespace talus
