#include "talus/solver/newton.hpp"

#include "talus/core/add_seconds.hpp"
#include "talus/core/errors.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <fmt/format.h>
#include <kinsol/kinsol.h>
#include <nvector/nvector_parallel.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_matrix.h>

namespace talus {

namespace {

// This process's entries (all of them, or a distributed run's owned ones).
Eigen::Map<Eigen::VectorXd> view(N_Vector v) {
  const sunindextype n =
      N_VGetVectorID(v) == SUNDIALS_NVEC_PARALLEL ? N_VGetLocalLength_Parallel(v) : N_VGetLength(v);
  return {N_VGetArrayPointer(v), static_cast<Eigen::Index>(n)};
}

// Everything the C callbacks need, reached through KINSOL's user data and the content pointer
// of the custom linear solver. Exceptions never cross the C boundary: the first one is kept
// and re-thrown once KINSol has returned.
struct Driver {
  NonlinearSystem& system;
  LinearSolver& linear;
  const NewtonOptions& options;
  NewtonReport report;
  const SparseMatrix* jacobian = nullptr;
  std::exception_ptr error;
  bool stagnated = false; ///< stopped past the iterations every attempt gets, without progress
  std::string kinsol_message;
  Eigen::VectorXd r;
};

int residual_callback(N_Vector u, N_Vector f, void* data) {
  auto& d = *static_cast<Driver*>(data);
  try {
    ++d.report.residual_evaluations;
    const bool ok = d.system.residual(view(u), d.r);
    if (!ok)
      return 1; // recoverable: KINSOL's line search shortens the step
    view(f) = d.r;
    return 0;
  } catch (...) {
    d.error = std::current_exception();
    return -1;
  }
}

// Past the iterations every attempt gets, an attempt goes on only while its residual keeps
// falling, by a quarter over a window of iterates (the same decision on every rank: the norms
// are global). A line search that crawls (5 % an iterate near a limit point) goes on; one that
// stands still stops.
bool stagnates(const std::vector<double>& history, const NewtonOptions& options) {
  const auto k = static_cast<int>(history.size()) - 1;
  if (k < options.max_iterations)
    return false;
  const double before = history[static_cast<std::size_t>(std::max(0, k - options.progress_window))];
  return !(history.back() <= 0.75 * before);
}

int jacobian_callback(N_Vector u, N_Vector fu, SUNMatrix, void* data, N_Vector, N_Vector) {
  auto& d = *static_cast<Driver*>(data);
  try {
    d.report.residual_history.push_back(N_VMaxNorm(fu) / d.options.residual_scale); // all ranks
    if (stagnates(d.report.residual_history, d.options)) {
      d.stagnated = true;
      return -1; // ends KINSol
    }
    d.jacobian = &d.system.jacobian(view(u));
    return 0;
  } catch (...) {
    d.error = std::current_exception();
    return -1;
  }
}

Driver& driver_of(SUNLinearSolver ls) {
  return *static_cast<Driver*>(ls->content);
}

SUNLinearSolver_Type ls_type(SUNLinearSolver) {
  return SUNLINEARSOLVER_DIRECT;
}

int ls_setup(SUNLinearSolver ls, SUNMatrix) {
  auto& d = driver_of(ls);
  try {
    if (d.system.pattern_changed()) {
      const AddSeconds timer(d.report.seconds_analysis);
      d.linear.analyze(*d.jacobian);
      d.system.pattern_analysed();
      ++d.report.symbolic_analyses;
    }
    const AddSeconds timer(d.report.seconds_factorization);
    d.linear.factorize(*d.jacobian);
    ++d.report.factorizations;
    return 0;
  } catch (...) {
    d.error = std::current_exception();
    return SUNLS_PACKAGE_FAIL_UNREC;
  }
}

int ls_solve(SUNLinearSolver ls, SUNMatrix, N_Vector x, N_Vector b, realtype) {
  auto& d = driver_of(ls);
  try {
    const AddSeconds timer(d.report.seconds_solve);
    Eigen::VectorXd solution;
    d.report.linear_iterations += d.linear.solve(view(b), solution).iterations;
    view(x) = solution;
    ++d.report.linear_solves;
    return 0;
  } catch (...) {
    d.error = std::current_exception();
    return SUNLS_PACKAGE_FAIL_UNREC;
  }
}

int ls_initialize(SUNLinearSolver) {
  return 0;
}
int ls_free(SUNLinearSolver ls) {
  ls->content = nullptr;
  SUNLinSolFreeEmpty(ls);
  return 0;
}

// The Jacobian lives in our own sparse format; KINSOL only needs a matrix object to pass
// around, and clears it (a no-op here) before each setup.
SUNMatrix_ID matrix_id(SUNMatrix) {
  return SUNMATRIX_CUSTOM;
}
int matrix_zero(SUNMatrix) {
  return 0;
}
void matrix_destroy(SUNMatrix A) {
  SUNMatFreeEmpty(A);
}

void error_handler(int code, const char* module, const char* function, char* message, void* data) {
  auto& d = *static_cast<Driver*>(data);
  d.kinsol_message = fmt::format("{} ({}, {}: code {})", message, module, function, code);
}

// Owns every SUNDIALS object of one solve and frees them in reverse order.
struct KinsolSession {
  SUNContext context = nullptr;
  N_Vector u = nullptr, u_scale = nullptr, f_scale = nullptr;
  SUNLinearSolver ls = nullptr;
  SUNMatrix J = nullptr;
  void* kinsol = nullptr;

  KinsolSession(const NonlinearSystem& system, Driver& d) {
    // Vectors over several ranks take their norms and dot products over all of them; on one
    // rank the serial vectors do the same without MPI (a serial run never starts it).
    const Communicator* comm = system.communicator();
    const bool spread = comm && comm->distributed();
    MPI_Comm mpi = spread ? comm->mpi() : MPI_COMM_NULL;
    if (SUNContext_Create(spread ? &mpi : nullptr, &context) < 0)
      throw std::runtime_error("SUNContext_Create failed");
    const auto n = static_cast<sunindextype>(system.size());
    auto make = [&] {
      return spread
                 ? N_VNew_Parallel(mpi, n, static_cast<sunindextype>(system.global_size()), context)
                 : N_VNew_Serial(n, context);
    };
    u = make();
    u_scale = make();
    f_scale = make();
    ls = SUNLinSolNewEmpty(context);
    J = SUNMatNewEmpty(context);
    kinsol = KINCreate(context);
    if (!u || !u_scale || !f_scale || !ls || !J || !kinsol)
      throw std::runtime_error("cannot allocate the KINSOL objects");
    ls->content = &d;
    ls->ops->gettype = ls_type;
    ls->ops->initialize = ls_initialize;
    ls->ops->setup = ls_setup;
    ls->ops->solve = ls_solve;
    ls->ops->free = ls_free;
    J->ops->getid = matrix_id;
    J->ops->zero = matrix_zero;
    J->ops->destroy = matrix_destroy;
  }
  ~KinsolSession() {
    if (kinsol)
      KINFree(&kinsol);
    if (J)
      SUNMatDestroy(J);
    if (ls)
      SUNLinSolFree(ls);
    for (N_Vector v : {u, u_scale, f_scale})
      if (v)
        N_VDestroy(v);
    if (context)
      SUNContext_Free(&context);
  }
  KinsolSession(const KinsolSession&) = delete;
  KinsolSession& operator=(const KinsolSession&) = delete;
};

void check(int flag, const char* what) {
  if (flag < 0)
    throw std::runtime_error(fmt::format("KINSOL setup failed in {} (flag {})", what, flag));
}

} // namespace

NewtonReport solve_newton(NonlinearSystem& system, LinearSolver& linear_solver, Eigen::VectorXd& x,
                          const NewtonOptions& options) {
  const auto n = static_cast<sunindextype>(system.size());
  if (x.size() != n)
    throw std::invalid_argument("solve_newton: initial guess has the wrong size");
  // KINSOL's line search does not end on overflowed norms: refuse scales it cannot use.
  for (const double v : {options.residual_scale, options.step_scale, options.residual_tolerance,
                         1.0 / options.residual_scale, 1.0 / options.step_scale})
    if (!std::isfinite(v) || v <= 0)
      throw std::invalid_argument(fmt::format(
          "solve_newton: scales and tolerance must be positive and finite (residual scale {:g}, "
          "step scale {:g}, tolerance {:g})",
          options.residual_scale, options.step_scale, options.residual_tolerance));
  Driver d{system, linear_solver, options, {}, nullptr, nullptr, false, {}, {}};
  KinsolSession k(system, d);
  view(k.u) = x;
  N_VConst(1.0 / options.step_scale, k.u_scale);
  N_VConst(1.0 / options.residual_scale, k.f_scale);

  check(KINInit(k.kinsol, residual_callback, k.u), "KINInit");
  check(KINSetUserData(k.kinsol, &d), "KINSetUserData");
  check(KINSetErrHandlerFn(k.kinsol, error_handler, &d), "KINSetErrHandlerFn");
  check(KINSetLinearSolver(k.kinsol, k.ls, k.J), "KINSetLinearSolver");
  check(KINSetJacFn(k.kinsol, jacobian_callback), "KINSetJacFn");
  check(KINSetMaxSetupCalls(k.kinsol, 1), "KINSetMaxSetupCalls"); // exact Newton: new J each step
  check(KINSetNumMaxIters(k.kinsol, std::max(1, options.extension) * options.max_iterations),
        "KINSetNumMaxIters");
  check(KINSetFuncNormTol(k.kinsol, options.residual_tolerance), "KINSetFuncNormTol");
  check(KINSetScaledStepTol(k.kinsol, options.step_tolerance), "KINSetScaledStepTol");
  check(KINSetMaxNewtonStep(k.kinsol, 1e300), "KINSetMaxNewtonStep"); // loads set the scale
  const int flag =
      KINSol(k.kinsol, k.u, options.line_search ? KIN_LINESEARCH : KIN_NONE, k.u_scale, k.f_scale);
  long iterations = 0;
  KINGetNumNonlinSolvIters(k.kinsol, &iterations);
  d.report.iterations = static_cast<int>(iterations);
  double fnorm = 0;
  KINGetFuncNorm(k.kinsol, &fnorm);
  d.report.converged = flag == KIN_SUCCESS || flag == KIN_INITIAL_GUESS_OK ||
                       (flag == KIN_STEP_LT_STPTOL && fnorm <= options.residual_tolerance);
  if (d.report.residual_history.empty() || d.report.converged)
    d.report.residual_history.push_back(fnorm);
  if (d.report.converged) {
    x = view(k.u);
    return d.report;
  }
  d.report.message = d.stagnated
                         ? fmt::format("no progress after {} iterations (the residual fell by less "
                                       "than a quarter over the last {})",
                                       iterations, options.progress_window)
                     : d.kinsol_message.empty()
                         ? fmt::format("KINSOL flag {} after {} iterations", flag, iterations)
                         : d.kinsol_message;
  // A failed factorisation is a Newton failure the load stepper may recover from by cutting
  // back; any other C++ error raised inside a callback propagates.
  if (d.error) {
    try {
      std::rethrow_exception(d.error);
    } catch (const SingularPivot& e) {
      d.report.message = e.what() + system.describe_unknown(e.unknown());
    } catch (const NumericalError& e) {
      d.report.message = e.what();
    }
  }
  return d.report;
}

} // namespace talus
