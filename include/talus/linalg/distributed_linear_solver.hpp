#pragma once
// The linear algebra of a distributed implicit step (Tpetra, Belos, MueLu). Each rank numbers
// the unknowns it sees: those it owns first, local ids [0, owned), then its ghosts (unknowns
// of nodes it shares with a rank that owns them); every unknown has a global id, owned by
// exactly one rank. A rank assembles its residual and tangent from its own points on all the
// unknowns it sees; the whole system is the sum over the ranks (a Tpetra Export with ADD onto
// the owners' rows), and every vector the Newton iteration handles is the owned part.
//
// As a LinearSolver: analyze() and factorize() take this rank's share of the matrix on the
// unknowns it sees (local ids, square); analyze() builds the distributed graph (per
// connectivity), factorize() adds the shares into it in place and sets up the preconditioner;
// solve() takes and returns the owned parts of b and x. Every call is collective.
//
// C++17: compiled into the Trilinos library as well.
#include "talus/core/types.hpp"
#include "talus/linalg/linear_solver.hpp"

#include <mpi.h>

#include <memory>
#include <vector>

namespace talus {

class DistributedLinearSolver : public LinearSolver {
public:
  /// The step's unknowns: overlap_gids[l] is the global id of local unknown l, the first
  /// owned_count of them owned here; global_count: the unknowns of all ranks. Collective.
  virtual void set_unknowns(const std::vector<Index>& overlap_gids, Index owned_count,
                            Index global_count) = 0;
  /// overlap[l] = the owner's value of local unknown l (an Import). Collective.
  virtual void import_ghosts(const Eigen::VectorXd& owned, Eigen::VectorXd& overlap) const = 0;
  /// owned[i] = the sum over the ranks of their overlap values of owned unknown i (an Export
  /// with ADD), added in a fixed order. Collective.
  virtual void export_add(const Eigen::VectorXd& overlap, Eigen::VectorXd& owned) const = 0;
  /// Whether set_coordinates() is worth calling before the next factorize().
  virtual bool uses_coordinates() const { return true; }
  /// Where each unknown sits (one row per local unknown, its node's coordinates): MueLu moves
  /// its coarse levels onto one rank by them, for an exact coarse solve. Kept until replaced.
  virtual void set_coordinates(Eigen::MatrixXd xyz) = 0;
  /// Whether an analysis outlives the step that numbered the unknowns: true where a step's
  /// matrix with the pattern of the last one analysed is the same operator's pattern (local ids
  /// are the global ones); false where every step numbers its unknowns anew over the ranks.
  virtual bool keeps_analysis_across_steps() const { return false; }
};

/// Belos CG (kind trilinos_cg) or GMRES (trilinos_gmres) with MueLu smoothed aggregation over
/// the ranks of `comm`. Throws std::invalid_argument for another kind, or in a binary built
/// without Trilinos.
std::unique_ptr<DistributedLinearSolver>
make_distributed_linear_solver(const LinearSolverOptions& options, MPI_Comm comm);

/// The linear solver of a step whose unknowns are spread over `ranks` ranks of `comm`: on one
/// rank the serial backend `options.kind`, owning every unknown (ghost import and export-add
/// are the identity); on several, Belos over the ranks, CG for a symmetric tangent and GMRES
/// otherwise (the serial backends cannot take a matrix held in shares).
std::unique_ptr<DistributedLinearSolver>
make_rank_linear_solver(LinearSolverOptions options, bool symmetric, int ranks, MPI_Comm comm);

} // namespace talus
