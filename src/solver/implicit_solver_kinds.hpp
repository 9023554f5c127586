#pragma once
// The implicit solver's instantiations, one file each (implicit_solver_impl.hpp): plane strain,
// axisymmetry and 3D, each for every shape function.
#include "talus/scene/scene.hpp"
#include "talus/solver/implicit_solver.hpp"

#include <memory>

namespace talus::implicit_detail {

/// The solver of the case's shape function for points in Dim dimensions (Axisymmetric: r, z).
template <int Dim, bool Axisymmetric>
std::unique_ptr<ImplicitSolver> make_solver_for_shape(Scene<Dim>& scene,
                                                      double prescribed_fraction_reached);

extern template std::unique_ptr<ImplicitSolver> make_solver_for_shape<2, false>(Scene<2>&, double);
extern template std::unique_ptr<ImplicitSolver> make_solver_for_shape<2, true>(Scene<2>&, double);
extern template std::unique_ptr<ImplicitSolver> make_solver_for_shape<3, false>(Scene<3>&, double);

} // namespace talus::implicit_detail
