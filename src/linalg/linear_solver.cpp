// Factory and names for the sparse linear-solver backends (see linear_solver.hpp).
// The backends themselves: suitesparse_solvers.cpp (CHOLMOD, UMFPACK, KLU), eigen_solvers.cpp
// (CG, BiCGSTAB) and, when built with TALUS_HAVE_TRILINOS, trilinos/trilinos_solver.cpp.
#include "talus/linalg/linear_solver.hpp"
#include "talus/linalg/distributed_linear_solver.hpp"

#ifdef TALUS_HAVE_TRILINOS
#include "trilinos/trilinos_solver.hpp"
#endif

#include <array>
#include <stdexcept>
#include <utility>

namespace talus {

namespace detail {
// Defined in suitesparse_solvers.cpp.
std::unique_ptr<LinearSolver> make_cholmod_solver();
std::unique_ptr<LinearSolver> make_umfpack_solver();
std::unique_ptr<LinearSolver> make_klu_solver();
// Defined in eigen_solvers.cpp.
std::unique_ptr<LinearSolver> make_eigen_cg_solver(const LinearSolverOptions& options);
std::unique_ptr<LinearSolver> make_eigen_bicgstab_solver(const LinearSolverOptions& options);
} // namespace detail

namespace {

constexpr std::array<std::pair<LinearSolverKind, const char*>, 7> kNames{{
    {LinearSolverKind::Cholmod, "cholmod"},
    {LinearSolverKind::Umfpack, "umfpack"},
    {LinearSolverKind::Klu, "klu"},
    {LinearSolverKind::EigenCg, "eigen_cg"},
    {LinearSolverKind::EigenBicgstab, "eigen_bicgstab"},
    {LinearSolverKind::TrilinosCg, "trilinos_cg"},
    {LinearSolverKind::TrilinosGmres, "trilinos_gmres"},
}};

bool is_built(LinearSolverKind kind) {
  switch (kind) {
  case LinearSolverKind::Cholmod:
  case LinearSolverKind::Umfpack:
  case LinearSolverKind::Klu:
  case LinearSolverKind::EigenCg:
  case LinearSolverKind::EigenBicgstab:
    return true;
  case LinearSolverKind::TrilinosCg:
  case LinearSolverKind::TrilinosGmres:
#ifdef TALUS_HAVE_TRILINOS
    return true;
#else
    return false;
#endif
  }
  return false;
}

} // namespace

std::unique_ptr<LinearSolver> make_linear_solver(const LinearSolverOptions& options) {
  switch (options.kind) {
  case LinearSolverKind::Cholmod:
    return detail::make_cholmod_solver();
  case LinearSolverKind::Umfpack:
    return detail::make_umfpack_solver();
  case LinearSolverKind::Klu:
    return detail::make_klu_solver();
  case LinearSolverKind::EigenCg:
    return detail::make_eigen_cg_solver(options);
  case LinearSolverKind::EigenBicgstab:
    return detail::make_eigen_bicgstab_solver(options);
  case LinearSolverKind::TrilinosCg:
  case LinearSolverKind::TrilinosGmres:
#ifdef TALUS_HAVE_TRILINOS
    return detail::make_trilinos_solver(options);
#else
    break;
#endif
  }
  throw std::invalid_argument("linear solver '" + to_string(options.kind) +
                              "' is not built into this binary");
}

std::unique_ptr<DistributedLinearSolver>
make_distributed_linear_solver(const LinearSolverOptions& options, MPI_Comm comm) {
#ifdef TALUS_HAVE_TRILINOS
  return detail::make_distributed_trilinos_solver(options, comm);
#else
  (void)comm;
  throw std::invalid_argument("linear solver '" + to_string(options.kind) +
                              "' cannot run distributed: this binary was built without Trilinos");
#endif
}

LinearSolverKind automatic_linear_solver(bool symmetric, int dimension, long long unknowns) {
  const LinearSolverKind iterative =
      symmetric ? LinearSolverKind::TrilinosCg : LinearSolverKind::TrilinosGmres;
  if (dimension == 3 && unknowns >= kIterativeUnknowns3d && is_built(iterative))
    return iterative;
  return symmetric ? LinearSolverKind::Cholmod : LinearSolverKind::Umfpack;
}

LinearSolverKind implicit_linear_solver(const std::string& chosen, bool symmetric, int dimension,
                                        long long unknowns) {
  if (chosen.empty())
    return automatic_linear_solver(symmetric, dimension, unknowns);
  LinearSolverKind kind;
  if (!parse_linear_solver_kind(chosen, kind))
    throw std::invalid_argument("unknown linear solver " + chosen);
  return kind;
}

std::vector<std::string> available_linear_solvers() {
  std::vector<std::string> names;
  for (const auto& [kind, name] : kNames) {
    if (is_built(kind)) {
      names.emplace_back(name);
    }
  }
  return names;
}

std::string to_string(LinearSolverKind kind) {
  for (const auto& [k, name] : kNames) {
    if (k == kind) {
      return name;
    }
  }
  return "unknown";
}

bool parse_linear_solver_kind(const std::string& name, LinearSolverKind& kind) {
  for (const auto& [k, n] : kNames) {
    if (name == n) {
      kind = k;
      return true;
    }
  }
  return false;
}

} // namespace talus
