#include "talus/solver/implicit_solver.hpp"
#include "implicit_solver_kinds.hpp"

namespace talus {

template <int Dim>
std::unique_ptr<ImplicitSolver> make_implicit_solver(Scene<Dim>& scene,
                                                     double prescribed_fraction_reached) {
  if constexpr (Dim == 2)
    if (scene.spec.geometry == Geometry::Axisymmetric)
      return implicit_detail::make_solver_for_shape<2, true>(scene, prescribed_fraction_reached);
  return implicit_detail::make_solver_for_shape<Dim, false>(scene, prescribed_fraction_reached);
}

template std::unique_ptr<ImplicitSolver> make_implicit_solver<2>(Scene<2>&, double);
template std::unique_ptr<ImplicitSolver> make_implicit_solver<3>(Scene<3>&, double);

} // namespace talus
