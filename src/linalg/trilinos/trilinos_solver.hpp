#pragma once
// Private to src/linalg: the Trilinos backends live in their own static library (talus_trilinos,
// compiled only when TALUS_HAVE_TRILINOS is set) so that the heavy Trilinos headers stay out of
// every other translation unit. make_linear_solver() calls this factory.
#include "talus/linalg/distributed_linear_solver.hpp"
#include "talus/linalg/linear_solver.hpp"

#include <memory>

namespace talus::detail {

/// Belos CG (options.kind == TrilinosCg) or GMRES (TrilinosGmres) on a Tpetra::CrsMatrix over
/// MPI_COMM_WORLD, preconditioned by MueLu smoothed aggregation (options.preconditioner "muelu"
/// or empty) or Ifpack2 (RILUK for CG, ILUT for GMRES; "ifpack2"). Initialises MPI and Kokkos
/// on first use if nobody has (singleton MPI without mpirun); they are finalised by an atexit
/// handler, so a Trilinos solver must not outlive main() (no static LinearSolver objects).
/// Throws std::invalid_argument for another kind or an unknown preconditioner name.
std::unique_ptr<LinearSolver> make_trilinos_solver(const LinearSolverOptions& options);

/// make_distributed_linear_solver() with Trilinos (distributed_solver.cpp).
std::unique_ptr<DistributedLinearSolver>
make_distributed_trilinos_solver(const LinearSolverOptions& options, MPI_Comm comm);

/// Initialises MPI (singleton MPI_COMM_WORLD when started without mpirun) and Kokkos once, unless
/// the application already did; Tpetra::finalize at exit undoes only what it did itself. Every
/// use of Trilinos (the solvers, Zoltan2) calls it first.
void ensure_tpetra_initialized();

} // namespace talus::detail
