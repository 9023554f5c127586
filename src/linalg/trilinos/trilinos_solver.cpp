// Trilinos backends: Belos CG / GMRES on a Tpetra::CrsMatrix, preconditioned by MueLu smoothed
// aggregation or Ifpack2 incomplete factorisations.
//
// Data layout: the Eigen matrix handed to us is the whole system, identical on every process
// (talus assembles serially). The Tpetra objects are nevertheless distributed: the row map is a
// uniform contiguous distribution of the global rows over MPI_COMM_WORLD, each process inserts
// only the rows it owns and fills only its part of b, and the solution is gathered back onto every
// process through an Import into a locally replicated map. With one rank (the usual case, also
// `talus` without mpirun) the process owns every row.
#include "trilinos_solver.hpp"

#include "belos_muelu.hpp"
#include "talus/core/errors.hpp"

#include <Ifpack2_Factory.hpp>
#include <MueLu_CreateTpetraPreconditioner.hpp>
#include <Teuchos_ParameterList.hpp>
#include <Tpetra_Core.hpp>
#include <Tpetra_CrsGraph.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Import.hpp>
#include <Tpetra_Map.hpp>
#include <Tpetra_MultiVector.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

namespace talus::detail {
namespace {

using graph_type = Tpetra::CrsGraph<LO, GO, NO>;
using row_matrix_type = Tpetra::RowMatrix<SC, LO, GO, NO>;
using import_type = Tpetra::Import<LO, GO, NO>;
using ifpack_type = Ifpack2::Preconditioner<SC, LO, GO, NO>;
using RowMajorMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;

enum class Precond { MueLu, Ifpack2 };

class TrilinosSolver final : public LinearSolver {
public:
  TrilinosSolver(bool cg, Precond precond, double tolerance, int max_iterations)
      : cg_(cg), precond_(precond), tolerance_(tolerance), max_iterations_(max_iterations) {
    ensure_tpetra_initialized();
    comm_ = Tpetra::getDefaultComm(); // MPI_COMM_WORLD
  }

  std::string name() const override { return cg_ ? "trilinos_cg" : "trilinos_gmres"; }
  bool requires_symmetric() const override { return cg_; }
  bool uses_near_null_space() const override { return precond_ == Precond::MueLu; }
  void set_near_null_space(Eigen::MatrixXd modes) override { near_null_space_ = std::move(modes); }

  void analyze(const SparseMatrix& A) override {
    if (A.rows() != A.cols()) {
      throw std::invalid_argument(name() + ": matrix is not square");
    }
    analyzed_ = false;
    factorized_ = false;
    prec_ = Teuchos::null;
    ifpack_ = Teuchos::null;
    rows_ = A; // CSC -> CSR copy: Tpetra is filled by rows
    rows_.makeCompressed();
    const auto n = static_cast<Tpetra::global_size_t>(A.rows());

    map_ = Teuchos::rcp(new map_type(n, GO{0}, comm_)); // this process's rows
    replicated_map_ = Teuchos::rcp(new map_type(n, GO{0}, comm_, Tpetra::LocallyReplicated));
    gather_ = Teuchos::rcp(new import_type(map_, replicated_map_));

    const auto local_rows = map_->getNodeNumElements();
    std::vector<size_t> counts(local_rows);
    for (size_t lr = 0; lr < local_rows; ++lr) {
      const auto g = static_cast<Eigen::Index>(map_->getGlobalElement(static_cast<LO>(lr)));
      counts[lr] = static_cast<size_t>(rows_.outerIndexPtr()[g + 1] - rows_.outerIndexPtr()[g]);
    }
    auto graph = Teuchos::rcp(new graph_type(map_, Teuchos::ArrayView<const size_t>(counts)));
    std::vector<GO> cols;
    for (size_t lr = 0; lr < local_rows; ++lr) {
      const GO g = map_->getGlobalElement(static_cast<LO>(lr));
      const auto begin = rows_.outerIndexPtr()[g];
      const auto end = rows_.outerIndexPtr()[g + 1];
      cols.assign(rows_.innerIndexPtr() + begin, rows_.innerIndexPtr() + end);
      if (!cols.empty()) {
        graph->insertGlobalIndices(g, Teuchos::ArrayView<const GO>(cols));
      }
    }
    graph->fillComplete();
    matrix_ = Teuchos::rcp(new matrix_type(Teuchos::rcp_implicit_cast<const graph_type>(graph)));
    fill_values(); // pattern-only preconditioner setup below needs a fill-complete matrix
    if (precond_ == Precond::Ifpack2) {
      ifpack_ = Ifpack2::Factory::create<row_matrix_type>(
          cg_ ? "RILUK" : "ILUT", Teuchos::rcp_implicit_cast<const row_matrix_type>(matrix_));
      Teuchos::ParameterList params;
      if (cg_) {
        params.set("fact: iluk level-of-fill", 1);
      } else {
        params.set("fact: ilut level-of-fill", 2.0);
        params.set("fact: drop tolerance", 0.0);
      }
      ifpack_->setParameters(params);
      ifpack_->initialize(); // symbolic
    }
    analyzed_ = true;
  }

  void factorize(const SparseMatrix& A) override {
    if (!analyzed_) {
      throw std::logic_error(name() + ": factorize() before analyze()");
    }
    factorized_ = false;
    RowMajorMatrix rows = A;
    rows.makeCompressed();
    if (!same_sparsity_pattern(rows, rows_)) {
      throw std::invalid_argument(name() +
                                  ": factorize() with a sparsity pattern that differs from the "
                                  "one given to analyze()");
    }
    rows_ = std::move(rows);
    fill_values();
    try {
      if (precond_ == Precond::Ifpack2) {
        ifpack_->compute();
        prec_ = ifpack_;
      } else {
        Teuchos::ParameterList params = muelu_parameters(comm_->getSize(), rows_.rows());
        if (near_null_space_.rows() == rows_.rows() && near_null_space_.cols() > 0)
          params.sublist("user data").set("Nullspace", null_space_vectors());
        prec_ = MueLu::CreateTpetraPreconditioner(Teuchos::rcp_implicit_cast<OP>(matrix_), params);
      }
    } catch (const std::exception& e) {
      throw NumericalError(
          fmt::format("{}: preconditioner setup failed: {}", description(), e.what()));
    }
    factorized_ = true;
  }

  LinearSolveStats solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) override {
    if (!factorized_) {
      throw std::logic_error(name() + ": solve() before a successful factorize()");
    }
    const Eigen::Index n = rows_.rows();
    if (b.size() != n) {
      throw std::invalid_argument(fmt::format(
          "{}: right-hand side has {} entries, matrix has {} rows", name(), b.size(), n));
    }
    const double bnorm = b.norm();
    if (bnorm == 0.0) {
      x.setZero(n);
      return {};
    }

    auto B = Teuchos::rcp(new MV(map_, 1));
    {
      auto data = B->getDataNonConst(0);
      for (size_t lr = 0; lr < map_->getNodeNumElements(); ++lr) {
        data[lr] = b(static_cast<Eigen::Index>(map_->getGlobalElement(static_cast<LO>(lr))));
      }
    }
    auto X = Teuchos::rcp(new MV(map_, 1)); // zero initial guess
    const LinearSolveStats stats =
        belos_solve(cg_, matrix_, prec_, X, B, tolerance_, max_iterations_, description());
    MV all(replicated_map_, 1);
    all.doImport(*X, *gather_, Tpetra::INSERT);
    auto data = all.getData(0);
    x.resize(n);
    for (Eigen::Index i = 0; i < n; ++i)
      x(i) = data[static_cast<size_t>(i)]; // replicated map: local index == global index
    return stats;
  }

private:
  std::string description() const {
    return name() + (precond_ == Precond::MueLu ? " (MueLu)"
                     : cg_                      ? " (Ifpack2 RILUK)"
                                                : " (Ifpack2 ILUT)");
  }

  /// The near-null space as Tpetra vectors on this process's rows: MueLu's smoothed aggregation
  /// builds its tentative prolongator from them (for elasticity the rigid-body modes, without
  /// which it interpolates constants only and CG needs several times the iterations).
  Teuchos::RCP<MV> null_space_vectors() const {
    const auto modes = static_cast<size_t>(near_null_space_.cols());
    auto vectors = Teuchos::rcp(new MV(map_, modes));
    for (size_t m = 0; m < modes; ++m) {
      auto data = vectors->getDataNonConst(m);
      for (size_t lr = 0; lr < map_->getNodeNumElements(); ++lr)
        data[lr] =
            near_null_space_(static_cast<Eigen::Index>(map_->getGlobalElement(static_cast<LO>(lr))),
                             static_cast<Eigen::Index>(m));
    }
    return vectors;
  }

  /// Copies the values of rows_ into matrix_ (whose graph is rows_'s pattern) for owned rows.
  void fill_values() {
    if (matrix_->isFillComplete()) {
      matrix_->resumeFill();
    }
    std::vector<GO> cols;
    const auto local_rows = map_->getNodeNumElements();
    for (size_t lr = 0; lr < local_rows; ++lr) {
      const GO g = map_->getGlobalElement(static_cast<LO>(lr));
      const auto begin = rows_.outerIndexPtr()[g];
      const auto end = rows_.outerIndexPtr()[g + 1];
      if (begin == end) {
        continue;
      }
      cols.assign(rows_.innerIndexPtr() + begin, rows_.innerIndexPtr() + end);
      matrix_->replaceGlobalValues(
          g, Teuchos::ArrayView<const GO>(cols),
          Teuchos::ArrayView<const SC>(rows_.valuePtr() + begin, end - begin));
    }
    matrix_->fillComplete();
  }

  bool cg_;
  Precond precond_;
  double tolerance_;
  int max_iterations_;
  Teuchos::RCP<const Teuchos::Comm<int>> comm_;
  Teuchos::RCP<const map_type> map_;            ///< rows owned by this process
  Teuchos::RCP<const map_type> replicated_map_; ///< every row on every process (Eigen side)
  Teuchos::RCP<const import_type> gather_;      ///< map_ -> replicated_map_
  Teuchos::RCP<matrix_type> matrix_;
  Teuchos::RCP<ifpack_type> ifpack_;
  Teuchos::RCP<OP> prec_;
  RowMajorMatrix rows_;             ///< copy of the last A (pattern check, filling)
  Eigen::MatrixXd near_null_space_; ///< per unknown and mode (MueLu), empty: constants only
  bool analyzed_ = false;
  bool factorized_ = false;
};

} // namespace

void ensure_tpetra_initialized() {
  static std::once_flag once;
  std::call_once(once, [] {
    if (Tpetra::isInitialized()) {
      return;
    }
    static char program[] = "talus";
    static char* args[] = {program, nullptr};
    int argc = 1;
    char** argv = args;
    Tpetra::initialize(&argc, &argv);
    std::atexit([] { Tpetra::finalize(); });
  });
}

std::unique_ptr<LinearSolver> make_trilinos_solver(const LinearSolverOptions& options) {
  if (options.kind != LinearSolverKind::TrilinosCg &&
      options.kind != LinearSolverKind::TrilinosGmres) {
    throw std::invalid_argument("make_trilinos_solver: not a Trilinos solver kind");
  }
  Precond precond;
  if (options.preconditioner.empty() || options.preconditioner == "muelu") {
    precond = Precond::MueLu;
  } else if (options.preconditioner == "ifpack2") {
    precond = Precond::Ifpack2;
  } else {
    throw std::invalid_argument("unknown Trilinos preconditioner '" + options.preconditioner +
                                "' (expected \"muelu\" or \"ifpack2\")");
  }
  if (!(options.tolerance > 0.0) || options.max_iterations < 1) {
    throw std::invalid_argument("Trilinos solver: tolerance must be > 0 and max_iterations >= 1");
  }
  return std::make_unique<TrilinosSolver>(options.kind == LinearSolverKind::TrilinosCg, precond,
                                          options.tolerance, options.max_iterations);
}

} // namespace talus::detail
