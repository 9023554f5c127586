// The implicit solver in 3D, for every shape function (implicit_solver_impl.hpp).
#include "implicit_solver_impl.hpp"

namespace talus::implicit_detail {

template std::unique_ptr<ImplicitSolver> make_solver_for_shape<3, false>(Scene<3>&, double);

} // namespace talus::implicit_detail
