// A serial backend as the solver of a step on one rank: it owns every unknown, so the ghost
// import and the export-add copy, and its local numbering is the global one.
#include "talus/linalg/distributed_linear_solver.hpp"

#include <stdexcept>
#include <utility>

namespace talus {

namespace {

class OneRankLinearSolver final : public DistributedLinearSolver {
public:
  explicit OneRankLinearSolver(std::unique_ptr<LinearSolver> serial) : serial_(std::move(serial)) {}

  std::string name() const override { return serial_->name(); }
  bool requires_symmetric() const override { return serial_->requires_symmetric(); }
  void analyze(const SparseMatrix& A) override { serial_->analyze(A); }
  void factorize(const SparseMatrix& A) override { serial_->factorize(A); }
  LinearSolveStats solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) override {
    return serial_->solve(b, x);
  }
  bool uses_near_null_space() const override { return serial_->uses_near_null_space(); }
  void set_near_null_space(Eigen::MatrixXd modes) override {
    serial_->set_near_null_space(std::move(modes));
  }

  void set_unknowns(const std::vector<Index>& overlap_gids, Index owned_count,
                    Index global_count) override {
    if (owned_count != global_count || static_cast<Index>(overlap_gids.size()) != owned_count)
      throw std::logic_error("one rank owns every unknown of its step");
  }
  void import_ghosts(const Eigen::VectorXd& owned, Eigen::VectorXd& overlap) const override {
    overlap = owned;
  }
  void export_add(const Eigen::VectorXd& overlap, Eigen::VectorXd& owned) const override {
    owned = overlap;
  }
  bool uses_coordinates() const override { return false; } // no coarse levels to move
  void set_coordinates(Eigen::MatrixXd) override {}
  bool keeps_analysis_across_steps() const override { return true; }

private:
  std::unique_ptr<LinearSolver> serial_;
};

} // namespace

std::unique_ptr<DistributedLinearSolver>
make_rank_linear_solver(LinearSolverOptions options, bool symmetric, int ranks, MPI_Comm comm) {
  if (ranks == 1)
    return std::make_unique<OneRankLinearSolver>(make_linear_solver(options));
  options.kind = symmetric ? LinearSolverKind::TrilinosCg : LinearSolverKind::TrilinosGmres;
  return make_distributed_linear_solver(options, comm);
}

} // namespace talus
