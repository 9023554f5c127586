// The distributed linear algebra of an implicit step (distributed_linear_solver.hpp): Tpetra
// maps of the owned and the overlapping unknowns, an Import (owner -> ghosts) and an Export
// with ADD (each rank's share -> the owner), the tangent as a CrsMatrix on the overlap added
// into one on the owned rows, and Belos with MueLu on that.
//
// Why not Tpetra's FECrsMatrix: it assumes that a rank owning an element owns one of its
// nodes, and so keeps the owned rows' columns within the overlap's. Here a node belongs to the
// lowest rank whose points reach it, so another rank's point can couple an owned row to a
// column this rank never sees; the owned matrix gets its own graph from the export instead.
#include "belos_muelu.hpp"
#include "trilinos_solver.hpp"

#include "talus/core/errors.hpp"
#include "talus/linalg/distributed_linear_solver.hpp"

#include <MueLu_CreateTpetraPreconditioner.hpp>
#include <Teuchos_DefaultMpiComm.hpp>
#include <Tpetra_CrsGraph.hpp>
#include <Tpetra_Export.hpp>
#include <Tpetra_Import.hpp>
#include <Tpetra_Vector.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>
#include <type_traits>

namespace talus::detail {
namespace {

using graph_type = Tpetra::CrsGraph<LO, GO, NO>;
using vector_type = Tpetra::Vector<SC, LO, GO, NO>;
using import_type = Tpetra::Import<LO, GO, NO>;
using export_type = Tpetra::Export<LO, GO, NO>;
using RowMajorMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;

class TpetraDistributedSolver final : public DistributedLinearSolver {
public:
  TpetraDistributedSolver(bool cg, double tolerance, int max_iterations, MPI_Comm comm)
      : cg_(cg), tolerance_(tolerance), max_iterations_(max_iterations) {
    ensure_tpetra_initialized();
    comm_ = Teuchos::rcp(new Teuchos::MpiComm<int>(comm));
  }

  std::string name() const override { return cg_ ? "trilinos_cg" : "trilinos_gmres"; }
  bool requires_symmetric() const override { return cg_; }
  bool uses_near_null_space() const override { return true; }
  void set_near_null_space(Eigen::MatrixXd modes) override { near_null_space_ = std::move(modes); }
  void set_coordinates(Eigen::MatrixXd xyz) override { coordinates_ = std::move(xyz); }

  void set_unknowns(const std::vector<Index>& overlap_gids, Index owned_count,
                    Index global_count) override {
    if (owned_count < 0 || owned_count > static_cast<Index>(overlap_gids.size()))
      throw std::invalid_argument("set_unknowns: more owned unknowns than overlapping ones");
    const std::vector<GO> all(overlap_gids.begin(), overlap_gids.end());
    const auto owned = static_cast<std::size_t>(owned_count);
    const auto total = static_cast<Tpetra::global_size_t>(global_count);
    owned_map_ = Teuchos::rcp(
        new map_type(total, Teuchos::ArrayView<const GO>(all.data(), owned), GO{0}, comm_));
    overlap_map_ =
        Teuchos::rcp(new map_type(Teuchos::OrdinalTraits<Tpetra::global_size_t>::invalid(),
                                  Teuchos::ArrayView<const GO>(all), GO{0}, comm_));
    importer_ = Teuchos::rcp(new import_type(owned_map_, overlap_map_));
    exporter_ = Teuchos::rcp(new export_type(overlap_map_, owned_map_));
    overlap_matrix_ = Teuchos::null;
    matrix_ = Teuchos::null;
    prec_ = Teuchos::null;
    factorized_ = false;
  }

  void import_ghosts(const Eigen::VectorXd& owned, Eigen::VectorXd& overlap) const override {
    require_unknowns();
    vector_type from(owned_map_), to(overlap_map_);
    copy_in(owned, from);
    to.doImport(from, *importer_, Tpetra::INSERT);
    copy_out(to, overlap);
  }

  void export_add(const Eigen::VectorXd& overlap, Eigen::VectorXd& owned) const override {
    require_unknowns();
    vector_type from(overlap_map_), to(owned_map_);
    copy_in(overlap, from);
    to.doExport(from, *exporter_, Tpetra::ADD);
    copy_out(to, owned);
  }

  // The overlap's graph from this rank's pattern (columns in local ids of the overlap map),
  // and the owned rows' graph that the export of every rank's share makes.
  void analyze(const SparseMatrix& A) override {
    require_unknowns();
    const auto n = static_cast<Eigen::Index>(overlap_map_->getNodeNumElements());
    if (A.rows() != n || A.cols() != n)
      throw std::invalid_argument(fmt::format("{}: this rank's matrix is {} x {}, its unknowns {}",
                                              name(), A.rows(), A.cols(), n));
    factorized_ = false;
    rows_ = A;
    rows_.makeCompressed();
    std::size_t widest = 0;
    for (Eigen::Index r = 0; r < n; ++r)
      widest = std::max(widest, static_cast<std::size_t>(rows_.outerIndexPtr()[r + 1] -
                                                         rows_.outerIndexPtr()[r]));
    auto graph = Teuchos::rcp(new graph_type(overlap_map_, overlap_map_, widest));
    for (Eigen::Index r = 0; r < n; ++r)
      graph->insertLocalIndices(static_cast<LO>(r), columns_of(r));
    graph->fillComplete(owned_map_, owned_map_);
    overlap_matrix_ =
        Teuchos::rcp(new matrix_type(Teuchos::rcp_implicit_cast<const graph_type>(graph)));
    fill_overlap();
    // The export builds the owned rows' graph; the matrix refilled in place shares it (a
    // static graph: the export then adds into existing entries).
    const auto exported = Tpetra::exportAndFillCompleteCrsMatrix<matrix_type>(
        Teuchos::rcp_implicit_cast<const matrix_type>(overlap_matrix_), *exporter_, owned_map_,
        owned_map_);
    matrix_ = Teuchos::rcp(new matrix_type(exported->getCrsGraph()));
    matrix_->fillComplete(owned_map_, owned_map_);
  }

  // The shares' values added into the owned rows in place, then the preconditioner.
  void factorize(const SparseMatrix& A) override {
    if (matrix_.is_null())
      throw std::logic_error(name() + ": factorize() before analyze()");
    factorized_ = false;
    RowMajorMatrix rows = A;
    rows.makeCompressed();
    if (!same_sparsity_pattern(rows, rows_))
      throw std::invalid_argument(name() + ": factorize() with a sparsity pattern that differs "
                                           "from the one given to analyze()");
    rows_ = std::move(rows);
    fill_overlap();
    matrix_->resumeFill();
    matrix_->setAllToScalar(0.0);
    matrix_->doExport(*overlap_matrix_, *exporter_, Tpetra::ADD);
    matrix_->fillComplete(owned_map_, owned_map_);
    try {
      Teuchos::ParameterList params = muelu_parameters(
          comm_->getSize(), static_cast<long long>(owned_map_->getGlobalNumElements()));
      if (auto modes = owned_rows(near_null_space_); !modes.is_null())
        params.sublist("user data").set("Nullspace", modes);
      if (params.get<bool>("repartition: enable")) {
        auto xyz = owned_rows(coordinates_);
        if (xyz.is_null())
          throw std::logic_error("no coordinates for MueLu's repartitioning (set_coordinates)");
        params.sublist("user data").set("Coordinates", xyz);
      }
      prec_ = MueLu::CreateTpetraPreconditioner(Teuchos::rcp_implicit_cast<OP>(matrix_), params);
    } catch (const std::exception& e) {
      throw NumericalError(
          fmt::format("{}: preconditioner setup failed: {}", description(), e.what()));
    }
    factorized_ = true;
  }

  LinearSolveStats solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) override {
    if (!factorized_)
      throw std::logic_error(name() + ": solve() before a successful factorize()");
    auto B = Teuchos::rcp(new MV(owned_map_, 1));
    auto X = Teuchos::rcp(new MV(owned_map_, 1)); // zero initial guess
    {
      auto data = B->getDataNonConst(0);
      if (b.size() != static_cast<Eigen::Index>(data.size()))
        throw std::invalid_argument(fmt::format("{}: right-hand side has {} entries, this rank "
                                                "owns {} unknowns",
                                                name(), b.size(), data.size()));
      std::copy(b.data(), b.data() + b.size(), data.begin());
    }
    std::vector<SC> norm(1);
    B->norm2(Teuchos::ArrayView<SC>(norm));
    LinearSolveStats stats;
    if (norm[0] > 0.0)
      stats = belos_solve(cg_, matrix_, prec_, X, B, tolerance_, max_iterations_, description());
    auto data = X->getData(0);
    x = Eigen::Map<const Eigen::VectorXd>(data.getRawPtr(), static_cast<Eigen::Index>(data.size()));
    return stats;
  }

private:
  std::string description() const { return name() + " (MueLu, distributed)"; }

  /// The owned rows of a per-unknown table as Tpetra vectors (one per column); null if empty.
  Teuchos::RCP<MV> owned_rows(const Eigen::MatrixXd& table) const {
    const auto owned = owned_map_->getNodeNumElements();
    if (table.cols() == 0 || table.rows() < static_cast<Eigen::Index>(owned))
      return Teuchos::null;
    auto out = Teuchos::rcp(new MV(owned_map_, static_cast<std::size_t>(table.cols())));
    for (std::size_t c = 0; c < out->getNumVectors(); ++c) {
      auto data = out->getDataNonConst(c);
      for (std::size_t i = 0; i < owned; ++i)
        data[i] = table(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(c));
    }
    return out;
  }

  void require_unknowns() const {
    if (owned_map_.is_null())
      throw std::logic_error(name() + ": set_unknowns() first");
  }

  static void copy_in(const Eigen::VectorXd& from, vector_type& to) {
    auto data = to.getDataNonConst();
    if (from.size() != static_cast<Eigen::Index>(data.size()))
      throw std::invalid_argument(
          fmt::format("distributed vector: {} values for {} unknowns", from.size(), data.size()));
    std::copy(from.data(), from.data() + from.size(), data.begin());
  }
  static void copy_out(const vector_type& from, Eigen::VectorXd& to) {
    auto data = from.getData();
    to =
        Eigen::Map<const Eigen::VectorXd>(data.getRawPtr(), static_cast<Eigen::Index>(data.size()));
  }

  /// Row r's columns of rows_ (local ids; Eigen's and Tpetra's local ordinals are both int, so
  /// a view, not a copy per row and iterate).
  Teuchos::ArrayView<const LO> columns_of(Eigen::Index r) const {
    static_assert(std::is_same_v<LO, int>);
    const int begin = rows_.outerIndexPtr()[r], end = rows_.outerIndexPtr()[r + 1];
    return {rows_.innerIndexPtr() + begin, end - begin};
  }

  // rows_'s values into the overlap matrix (same pattern, local ids).
  void fill_overlap() {
    if (overlap_matrix_->isFillComplete())
      overlap_matrix_->resumeFill();
    for (Eigen::Index r = 0; r < rows_.rows(); ++r) {
      const int begin = rows_.outerIndexPtr()[r], end = rows_.outerIndexPtr()[r + 1];
      if (begin != end)
        overlap_matrix_->replaceLocalValues(
            static_cast<LO>(r), columns_of(r),
            Teuchos::ArrayView<const SC>(rows_.valuePtr() + begin, end - begin));
    }
    overlap_matrix_->fillComplete(owned_map_, owned_map_);
  }

  bool cg_;
  double tolerance_;
  int max_iterations_;
  Teuchos::RCP<const Teuchos::Comm<int>> comm_;
  Teuchos::RCP<const map_type> owned_map_, overlap_map_;
  Teuchos::RCP<const import_type> importer_;
  Teuchos::RCP<const export_type> exporter_;
  Teuchos::RCP<matrix_type> overlap_matrix_; ///< this rank's share, on the overlap
  Teuchos::RCP<matrix_type> matrix_;         ///< the sum of the shares, on the owned rows
  Teuchos::RCP<OP> prec_;
  RowMajorMatrix rows_; ///< this rank's last share (pattern check and values)
  Eigen::MatrixXd near_null_space_;
  Eigen::MatrixXd coordinates_; ///< per local unknown, its node's position (repartitioning)
  bool factorized_ = false;
};

} // namespace

std::unique_ptr<DistributedLinearSolver>
make_distributed_trilinos_solver(const LinearSolverOptions& options, MPI_Comm comm) {
  if (options.kind != LinearSolverKind::TrilinosCg &&
      options.kind != LinearSolverKind::TrilinosGmres)
    throw std::invalid_argument(
        "a distributed run solves with trilinos_cg or trilinos_gmres, not " +
        to_string(options.kind));
  return std::make_unique<TpetraDistributedSolver>(options.kind == LinearSolverKind::TrilinosCg,
                                                   options.tolerance, options.max_iterations, comm);
}

} // namespace talus::detail
