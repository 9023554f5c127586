#pragma once
// Test access to the implicit step's assembly by shares of the points: the DOF-map, tangent and
// rigid-body-mode tests assemble a step in several shares of the points and compare the sum
// with one share, or with central differences. The solver itself steps as one share per rank
// (step()); nothing but the tests uses this interface, so it is no part of the public header.
#include "talus/linalg/dof_map.hpp"
#include "talus/linalg/node_layout.hpp"
#include "talus/solver/implicit_solver.hpp"
#include "talus/solver/particle_share.hpp"

#include <Eigen/Core>
#include <span>
#include <vector>

namespace talus {

class ImplicitShareAssembly {
public:
  virtual ~ImplicitShareAssembly() = default;
  /// The step's unknowns (all ranks'), as ImplicitSolver::unknowns().
  virtual Index unknowns() const = 0;
  /// Sets up the step that step(lambda_end, ramp_end, dt) would take: connectivity at the
  /// step's start, the global DOF numbering (unknowns() of them), node masses and loads.
  virtual void prepare(double lambda_end, double ramp_end, double dt) = 0;
  /// The global unknown of every (grid node, field, component), negative for none (held,
  /// prescribed or massless).
  virtual const NodeDofs& global_dofs() const = 0;
  /// Per grid node, the share that owns it: the lowest-indexed share whose points reach it;
  /// -1 for nodes no point reaches.
  virtual std::vector<int> node_owners(std::span<const ParticleShare> shares) const = 0;
  /// The grid nodes the share's assembly reaches, ascending: its points' stencils and the
  /// nodes of the ghost-penalty faces it assembles (those whose first on-face node it owns).
  virtual std::vector<Index> touched_nodes(const ParticleShare& share,
                                           std::span<const int> node_owner) const = 0;
  /// The share's DOF map over its touched nodes, numbered by the step's global DOFs.
  virtual DofMap dof_map(const ParticleShare& share, std::span<const int> node_owner) const = 0;
  /// Evaluates the share's points at the increment du_overlap (the share's DOFs in the local
  /// ids of `map`; the prescribed components follow the step's ramp) and assembles the share's
  /// residual (sized and set to the overlap DOFs) and/or tangent (set to the overlap DOFs' square
  /// matrix); either may be null. Returns false if a material update failed. Throws
  /// std::invalid_argument if the share reaches a node outside `map`.
  virtual bool assemble_share(const ParticleShare& share, const DofMap& map,
                              const Eigen::VectorXd& du_overlap, Eigen::VectorXd* residual,
                              SparseMatrix* tangent) = 0;
};

/// The share assembly of a solver make_implicit_solver made.
inline ImplicitShareAssembly& share_assembly(ImplicitSolver& solver) {
  return dynamic_cast<ImplicitShareAssembly&>(solver);
}

/// `count` contiguous shares of near-equal size covering the points [0, particle_count).
inline std::vector<ParticleShare> split_particles(Index particle_count, int count) {
  std::vector<ParticleShare> shares;
  for (int s = 0; s < count; ++s)
    shares.push_back({s, particle_count * s / count, particle_count * (s + 1) / count});
  return shares;
}

} // namespace talus
