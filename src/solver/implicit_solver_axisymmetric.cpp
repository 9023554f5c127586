// The implicit solver in axisymmetry, for every shape function (implicit_solver_impl.hpp).
#include "implicit_solver_impl.hpp"

namespace talus::implicit_detail {

template std::unique_ptr<ImplicitSolver> make_solver_for_shape<2, true>(Scene<2>&, double);

} // namespace talus::implicit_detail
