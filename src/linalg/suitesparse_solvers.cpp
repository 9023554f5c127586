// SuiteSparse direct solvers: CHOLMOD (sparse Cholesky), UMFPACK and KLU (sparse LU).
//
// Each solver keeps a compressed copy of the last matrix it was given: the SuiteSparse routines
// read Eigen's CSC arrays in place (int indices, 0-based, sorted row indices per column), UMFPACK's
// solve needs the matrix again for iterative refinement, and the true residual ||b - Ax|| / ||b||
// reported by solve() is computed from it.
#include "talus/core/errors.hpp"
#include "talus/linalg/linear_solver.hpp"

#include <cholmod.h>
#include <dlfcn.h>
#include <fmt/format.h>
#include <klu.h>
#include <omp.h>
#include <umfpack.h>

#include <algorithm>
#include <cmath>
#include <new>
#include <stdexcept>
#include <vector>

namespace talus {
namespace {

/// While alive, every OpenMP parallel region runs on the calling thread alone, and so does
/// OpenBLAS when it is the BLAS in use. Debian's CHOLMOD opens a parallel region of 4 threads
/// (its CHOLMOD_OMP_NUM_THREADS) for each large enough supernode to copy values; on 2 cores,
/// with waiting threads asleep, waking them thousands of times per factorisation cost more than
/// the factorisation (a 4068-unknown beam tangent: 41 ms of wall time for 13 ms of CPU, 1000
/// context switches per factorisation; serial 3.6 ms). OpenBLAS must follow: its OpenMP build
/// waits for workers that a serial region never starts. The supernodes of our 2D and mid-size
/// 3D tangents are too small for threaded BLAS to pay; the large 3D systems go to MueLu.
class SerialThreads {
public:
  SerialThreads() : levels_(omp_get_max_active_levels()), omp_threads_(omp_get_max_threads()) {
    omp_set_max_active_levels(0);
    if (blas_.set != nullptr) {
      blas_threads_ = blas_.get();
      blas_.set(1);
    }
  }
  ~SerialThreads() {
    if (blas_.set != nullptr)
      blas_.set(blas_threads_);
    omp_set_num_threads(omp_threads_); // OpenBLAS's OpenMP build sets OpenMP's count too
    omp_set_max_active_levels(levels_);
  }
  SerialThreads(const SerialThreads&) = delete;
  SerialThreads& operator=(const SerialThreads&) = delete;

private:
  /// OpenBLAS's thread controls, when the process's BLAS is OpenBLAS (any Debian flavour).
  struct OpenBlas {
    int (*get)() = nullptr;
    void (*set)(int) = nullptr;
  };
  static OpenBlas find_openblas() {
    OpenBlas b;
    b.get = reinterpret_cast<int (*)()>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
    if (b.get != nullptr)
      b.set = reinterpret_cast<void (*)(int)>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
    return b;
  }
  static inline const OpenBlas blas_ = find_openblas();
  int levels_, omp_threads_, blas_threads_ = 1;
};

/// Common bookkeeping: the compressed copy of A, call-order and pattern checks, true residual.
class DirectSolver : public LinearSolver {
public:
  bool requires_symmetric() const override { return false; }

protected:
  /// analyze(): takes a compressed copy of A.
  void store_pattern(const SparseMatrix& A) {
    if (A.rows() != A.cols()) {
      throw std::invalid_argument(name() + ": matrix is not square");
    }
    analyzed_ = false;
    factorized_ = false;
    A_ = A;
    A_.makeCompressed();
  }
  /// factorize(): takes the new values, which must come with the analysed pattern. A
  /// compressed A (the assembler's) gives only its values: no allocation, no pattern copy.
  void store_values(const SparseMatrix& A) {
    if (!analyzed_) {
      throw std::logic_error(name() + ": factorize() before analyze()");
    }
    factorized_ = false;
    if (!A.isCompressed()) {
      SparseMatrix compressed = A;
      compressed.makeCompressed();
      store_values(compressed);
      return;
    }
    if (!same_sparsity_pattern(A, A_)) {
      throw std::invalid_argument(name() +
                                  ": factorize() with a sparsity pattern that differs from the "
                                  "one given to analyze()");
    }
    std::copy(A.valuePtr(), A.valuePtr() + A.nonZeros(), A_.valuePtr());
  }
  void check_solve(const Eigen::VectorXd& b) const {
    if (!factorized_) {
      throw std::logic_error(name() + ": solve() before a successful factorize()");
    }
    if (b.size() != A_.rows()) {
      throw std::invalid_argument(fmt::format(
          "{}: right-hand side has {} entries, matrix has {} rows", name(), b.size(), A_.rows()));
    }
  }
  LinearSolveStats finish_solve(const Eigen::VectorXd& b, const Eigen::VectorXd& x) const {
    LinearSolveStats stats;
    stats.iterations = 1;
    const double bnorm = b.norm();
    const double rnorm = (b - A_ * x).norm();
    stats.relative_residual = bnorm > 0 ? rnorm / bnorm : rnorm;
    if (!std::isfinite(stats.relative_residual)) {
      throw NumericalError(name() + ": solution is not finite (matrix numerically singular?)");
    }
    return stats;
  }

  int n() const { return static_cast<int>(A_.rows()); }
  int* Ap() { return A_.outerIndexPtr(); }
  int* Ai() { return A_.innerIndexPtr(); }
  double* Ax() { return A_.valuePtr(); }

  SparseMatrix A_;
  bool analyzed_ = false;
  bool factorized_ = false;
};

// --- CHOLMOD --------------------------------------------------------------------------------

class CholmodSolver final : public DirectSolver {
public:
  CholmodSolver() {
    cholmod_start(&common_);
    common_.print = 0; // we report failures ourselves
  }
  ~CholmodSolver() override {
    if (L_ != nullptr) {
      cholmod_free_factor(&L_, &common_);
    }
    cholmod_finish(&common_);
  }
  CholmodSolver(const CholmodSolver&) = delete;
  CholmodSolver& operator=(const CholmodSolver&) = delete;

  std::string name() const override { return "cholmod"; }
  bool requires_symmetric() const override { return true; }

  void analyze(const SparseMatrix& A) override {
    store_pattern(A);
    if (L_ != nullptr) {
      cholmod_free_factor(&L_, &common_);
    }
    cholmod_sparse view = sparse_view();
    L_ = cholmod_analyze(&view, &common_);
    if (L_ == nullptr || common_.status < CHOLMOD_OK) {
      throw_failure("cholmod_analyze");
    }
    analyzed_ = true;
  }

  void factorize(const SparseMatrix& A) override {
    store_values(A);
    cholmod_sparse view = sparse_view();
    {
      const SerialThreads serial;
      cholmod_factorize(&view, L_, &common_);
    }
    if (common_.status == CHOLMOD_NOT_POSDEF || L_->minor < L_->n) {
      throw SingularPivot(original_column(L_->minor),
                          fmt::format("cholmod: matrix is not positive definite (Cholesky "
                                      "breaks down at column {} of {})",
                                      original_column(L_->minor), L_->n));
    }
    if (common_.status < CHOLMOD_OK) {
      throw_failure("cholmod_factorize");
    }
    // For small or very sparse matrices CHOLMOD picks a simplicial LDL' factorisation, which only
    // fails on a zero pivot and happily factorises indefinite matrices: A is positive definite
    // iff every entry of D is positive. (The supernodal path is LL' and fails above.)
    if (!L_->is_super && !L_->is_ll) {
      const auto* Lp = static_cast<const int*>(L_->p);
      const auto* Lx = static_cast<const double*>(L_->x);
      for (size_t j = 0; j < L_->n; ++j) {
        if (!(Lx[Lp[j]] > 0.0)) { // D(j) is stored first in column j
          throw SingularPivot(original_column(j),
                              fmt::format("cholmod: matrix is not positive definite (the pivot "
                                          "of column {} of {} is {:.3e})",
                                          original_column(j), L_->n, Lx[Lp[j]]));
        }
      }
    }
    factorized_ = true;
  }

  LinearSolveStats solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) override {
    check_solve(b);
    cholmod_dense rhs{};
    rhs.nrow = static_cast<size_t>(b.size());
    rhs.ncol = 1;
    rhs.nzmax = rhs.nrow;
    rhs.d = rhs.nrow;
    rhs.x = const_cast<double*>(b.data()); // read only
    rhs.xtype = CHOLMOD_REAL;
    rhs.dtype = CHOLMOD_DOUBLE;
    cholmod_dense* sol = cholmod_solve(CHOLMOD_A, L_, &rhs, &common_);
    if (sol == nullptr || common_.status < CHOLMOD_OK) {
      if (sol != nullptr) {
        cholmod_free_dense(&sol, &common_);
      }
      throw_failure("cholmod_solve");
    }
    x = Eigen::Map<const Eigen::VectorXd>(static_cast<const double*>(sol->x), b.size());
    cholmod_free_dense(&sol, &common_);
    return finish_solve(b, x);
  }

private:
  /// The column of A_ that column k of the factor (of the permuted matrix) belongs to.
  long long original_column(std::size_t k) const {
    const auto* perm = static_cast<const int*>(L_->Perm);
    return perm != nullptr && k < L_->n ? perm[k] : static_cast<long long>(k);
  }

  /// Symmetric view of A_ that uses only its lower triangle (A_ holds both triangles).
  cholmod_sparse sparse_view() {
    cholmod_sparse s{};
    s.nrow = static_cast<size_t>(A_.rows());
    s.ncol = static_cast<size_t>(A_.cols());
    s.nzmax = static_cast<size_t>(A_.nonZeros());
    s.p = Ap();
    s.i = Ai();
    s.nz = nullptr; // packed
    s.x = Ax();
    s.z = nullptr;
    s.stype = -1;
    s.itype = CHOLMOD_INT;
    s.xtype = CHOLMOD_REAL;
    s.dtype = CHOLMOD_DOUBLE;
    s.sorted = 1;
    s.packed = 1;
    return s;
  }

  [[noreturn]] void throw_failure(const char* what) const {
    if (common_.status == CHOLMOD_OUT_OF_MEMORY) {
      throw std::bad_alloc();
    }
    throw std::runtime_error(fmt::format("cholmod: {} failed (status {})", what, common_.status));
  }

  cholmod_common common_{};
  cholmod_factor* L_ = nullptr;
};

// --- UMFPACK --------------------------------------------------------------------------------

class UmfpackSolver final : public DirectSolver {
public:
  UmfpackSolver() { umfpack_di_defaults(control_); }
  ~UmfpackSolver() override { free_all(); }
  UmfpackSolver(const UmfpackSolver&) = delete;
  UmfpackSolver& operator=(const UmfpackSolver&) = delete;

  std::string name() const override { return "umfpack"; }

  void analyze(const SparseMatrix& A) override {
    store_pattern(A);
    free_all();
    const int status = umfpack_di_symbolic(n(), n(), Ap(), Ai(), Ax(), &symbolic_, control_, info_);
    if (status != UMFPACK_OK) {
      symbolic_ = nullptr;
      throw_failure("umfpack_di_symbolic", status);
    }
    analyzed_ = true;
  }

  void factorize(const SparseMatrix& A) override {
    store_values(A);
    free_numeric();
    const int status = umfpack_di_numeric(Ap(), Ai(), Ax(), symbolic_, &numeric_, control_, info_);
    if (status == UMFPACK_WARNING_singular_matrix) {
      const long long column = zero_pivot_column();
      free_numeric();
      throw SingularPivot(column, fmt::format("umfpack: matrix is singular (a zero pivot in "
                                              "column {} of {})",
                                              column, n()));
    }
    if (status < UMFPACK_OK) {
      free_numeric();
      throw_failure("umfpack_di_numeric", status);
    }
    factorized_ = true;
  }

  LinearSolveStats solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) override {
    check_solve(b);
    Eigen::VectorXd result(b.size());
    const int status = umfpack_di_solve(UMFPACK_A, Ap(), Ai(), Ax(), result.data(), b.data(),
                                        numeric_, control_, info_);
    if (status == UMFPACK_WARNING_singular_matrix) {
      throw NumericalError("umfpack: matrix is singular");
    }
    if (status < UMFPACK_OK) {
      throw_failure("umfpack_di_solve", status);
    }
    x = std::move(result);
    return finish_solve(b, x);
  }

private:
  /// The column of A whose pivot (diagonal of U) is zero, from a singular factorisation.
  long long zero_pivot_column() {
    std::vector<int> Q(static_cast<std::size_t>(n()));
    std::vector<double> diagonal(static_cast<std::size_t>(n()));
    int do_recip = 0;
    if (umfpack_di_get_numeric(nullptr, nullptr, nullptr, nullptr, nullptr, nullptr, nullptr,
                               Q.data(), diagonal.data(), &do_recip, nullptr,
                               numeric_) != UMFPACK_OK)
      return -1;
    const auto zero = std::find(diagonal.begin(), diagonal.end(), 0.0);
    return zero == diagonal.end() ? -1 : Q[static_cast<std::size_t>(zero - diagonal.begin())];
  }

  void free_numeric() {
    if (numeric_ != nullptr) {
      umfpack_di_free_numeric(&numeric_);
      numeric_ = nullptr;
    }
  }
  void free_all() {
    free_numeric();
    if (symbolic_ != nullptr) {
      umfpack_di_free_symbolic(&symbolic_);
      symbolic_ = nullptr;
    }
  }
  [[noreturn]] static void throw_failure(const char* what, int status) {
    if (status == UMFPACK_ERROR_out_of_memory) {
      throw std::bad_alloc();
    }
    throw std::runtime_error(fmt::format("umfpack: {} failed (status {})", what, status));
  }

  double control_[UMFPACK_CONTROL]{};
  double info_[UMFPACK_INFO]{};
  void* symbolic_ = nullptr;
  void* numeric_ = nullptr;
};

// --- KLU ------------------------------------------------------------------------------------

class KluSolver final : public DirectSolver {
public:
  KluSolver() { klu_defaults(&common_); }
  ~KluSolver() override { free_all(); }
  KluSolver(const KluSolver&) = delete;
  KluSolver& operator=(const KluSolver&) = delete;

  std::string name() const override { return "klu"; }

  void analyze(const SparseMatrix& A) override {
    store_pattern(A);
    free_all();
    symbolic_ = klu_analyze(n(), Ap(), Ai(), &common_);
    if (symbolic_ == nullptr) {
      throw_failure("klu_analyze");
    }
    analyzed_ = true;
  }

  void factorize(const SparseMatrix& A) override {
    store_values(A);
    if (numeric_ != nullptr) {
      // Same pattern: refactor with the previous pivot order. Without pivoting that can be
      // unstable for very different values, so fall back to a full factorisation when it fails
      // or when the pivot-based condition estimate degrades sharply.
      const int ok = klu_refactor(Ap(), Ai(), Ax(), symbolic_, numeric_, &common_);
      if (ok && common_.status == KLU_OK && klu_rcond(symbolic_, numeric_, &common_) &&
          common_.rcond > 1e-3 * rcond_at_factor_) {
        factorized_ = true;
        return;
      }
      klu_free_numeric(&numeric_, &common_);
    }
    numeric_ = klu_factor(Ap(), Ai(), Ax(), symbolic_, &common_);
    if (common_.status == KLU_SINGULAR) {
      if (numeric_ != nullptr) {
        klu_free_numeric(&numeric_, &common_);
      }
      const long long column = common_.singular_col < n() ? common_.singular_col : -1;
      throw SingularPivot(column, fmt::format("klu: matrix is singular (a zero pivot in column "
                                              "{} of {})",
                                              column, n()));
    }
    if (numeric_ == nullptr || common_.status < KLU_OK) {
      throw_failure("klu_factor");
    }
    rcond_at_factor_ = klu_rcond(symbolic_, numeric_, &common_) ? common_.rcond : 0.0;
    factorized_ = true;
  }

  LinearSolveStats solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) override {
    check_solve(b);
    Eigen::VectorXd result = b; // klu_solve overwrites the right-hand side with the solution
    if (!klu_solve(symbolic_, numeric_, n(), 1, result.data(), &common_)) {
      throw_failure("klu_solve");
    }
    x = std::move(result);
    return finish_solve(b, x);
  }

private:
  void free_all() {
    if (numeric_ != nullptr) {
      klu_free_numeric(&numeric_, &common_);
    }
    if (symbolic_ != nullptr) {
      klu_free_symbolic(&symbolic_, &common_);
    }
  }
  [[noreturn]] void throw_failure(const char* what) const {
    if (common_.status == KLU_OUT_OF_MEMORY) {
      throw std::bad_alloc();
    }
    throw std::runtime_error(fmt::format("klu: {} failed (status {})", what, common_.status));
  }

  klu_common common_{};
  klu_symbolic* symbolic_ = nullptr;
  klu_numeric* numeric_ = nullptr;
  double rcond_at_factor_ = 0.0;
};

} // namespace

namespace detail {
std::unique_ptr<LinearSolver> make_cholmod_solver() {
  return std::make_unique<CholmodSolver>();
}
std::unique_ptr<LinearSolver> make_umfpack_solver() {
  return std::make_unique<UmfpackSolver>();
}
std::unique_ptr<LinearSolver> make_klu_solver() {
  return std::make_unique<KluSolver>();
}
} // namespace detail

} // namespace talus
