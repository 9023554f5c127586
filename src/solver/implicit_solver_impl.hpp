#pragma once
// The implicit solver's one class for every dimension, shape function and geometry; each of
// implicit_solver_plane.cpp, implicit_solver_axisymmetric.cpp and implicit_solver_3d.cpp
// instantiates its share, so that the three compile side by side (one file took 110 s).
#include "implicit_commit.hpp"
#include "implicit_reactions.hpp"
#include "implicit_residual.hpp"
#include "implicit_share_assembly.hpp"
#include "implicit_solver_kinds.hpp"
#include "implicit_step_setup.hpp"
#include "implicit_tangent.hpp"
#include "implicit_trial_state.hpp"
#include "step_tangent.hpp"
#include "talus/core/add_seconds.hpp"
#include "talus/core/errors.hpp"
#include "talus/core/parallel.hpp"
#include "talus/grid/particle_grid_map.hpp"
#include "talus/linalg/distributed_linear_solver.hpp"
#include "talus/linalg/lattice_assembler.hpp"
#include "talus/linalg/linear_solver.hpp"
#include "talus/shape/shape_functions.hpp"
#include "talus/solver/energies.hpp"
#include "talus/solver/ghost_penalty.hpp"
#include "talus/solver/implicit_solver.hpp"
#include "talus/solver/rank_sums.hpp"
#include "talus/solver/rigid_body_modes.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string_view>
#include <type_traits>

namespace talus::implicit_detail {

// Newton's tolerance is never set below this multiple of the stress round-off force.
constexpr double kRoundOffFloor = 100.0;

// Axisymmetric (Dim 2 only): x = r, y = z, volumes per radian; the step gradient gains the hoop
// stretch dF33 = 1 + u_r / r_n (StepComponents), the internal force its term
// f_i,r += V0 G33 N_i / r_n, and the tangent the matching rows and columns.
template <int Dim, class Shape, bool Axisymmetric>
class ImplicitSolverImpl final : public ImplicitSolver,
                                 public ImplicitShareAssembly,
                                 NonlinearSystem {
  using V = Vec<Dim>;
  using M = Mat<Dim>;
  using Ghost = GhostPenalty<Dim>;
  using Components = StepComponents<Dim, Axisymmetric>;

public:
  ImplicitSolverImpl(Scene<Dim>& scene, double prescribed_fraction_reached)
      : scene_(scene), trial_(scene), ramp_committed_(prescribed_fraction_reached) {
    step_.lay_out(scene);
    double modulus = 0;
    for (const auto& m : scene.materials) {
      modulus = std::max(modulus, m->lame().p_wave_modulus());
      material_young_.push_back(m->lame().young_modulus());
    }
    round_off_force_ = std::numeric_limits<double>::epsilon() * modulus * scene.grid.cell_size();
    const bool symmetric = symmetric_implicit_tangent(scene.spec);
    comm_ = &scene.decomposition->comm();
    LinearSolverOptions options;
    options.kind = serial_linear_solver_kind(symmetric);
    linear_ = make_rank_linear_solver(options, symmetric, comm_->size(), comm_->mpi());
    const auto np = static_cast<std::size_t>(scene.particles.size());
    dynamic_ = scene.spec.analysis == AnalysisType::ImplicitDynamic;
    // A geostatic initial stress already balances the full weight: gravity then acts in full
    // from the first step, and only the other loads follow the load factor.
    gravity_ramped_ = !scene.spec.starts_geostatic();
    // A dynamic stage after another dynamic stage continues from its Newmark acceleration.
    if (dynamic_ && scene.particles.acceleration.size() != np)
      scene.particles.acceleration.assign(np, V::Zero());
    for (auto& r : reactions_)
      r.setZero();
  }

  NewtonReport step(double lambda_end, double ramp_end, double dt) override {
    prepare(lambda_end, ramp_end, dt);
    NewtonOptions options;
    options.residual_scale = step_.force_scale;
    // The stress carries an absolute round-off of about eps * E (the strain comes from F - I),
    // so no nodal force is known better than ~eps * E * h. A tolerance below 100 times that
    // floor would ask for digits that do not exist (stiff material, light load).
    options.residual_tolerance = std::max(scene_.spec.solver.newton_tolerance,
                                          kRoundOffFloor * round_off_force_ / step_.force_scale);
    options.step_scale = scene_.grid.cell_size();
    options.max_iterations = scene_.spec.solver.max_newton_iterations;
    // In dynamics a slow step is better cut back (a smaller dt is also more accurate); the
    // extension serves quasi-static loading towards a limit point, where a cut-back only stalls.
    if (dynamic_)
      options.extension = 1;
    Eigen::VectorXd du = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(size()));
    NewtonReport report;
    if (step_.global_dof_count == 0) {
      report.converged = true;
      report.residual_history.push_back(0.0);
    } else {
      // Plain Newton or KINSOL's line search, whichever converged the last step, then the
      // other before the stepper cuts the load step back. Plain Newton starts: from a
      // stress-free or strongly rotating state the first full step can raise the residual (a
      // bent beam's linearised step stretches its fibres) and a monotone line search then
      // crawls. Once plain Newton has failed (a slide, a yielding corner) the next steps start
      // with the line search rather than spend the iteration limit on a diverging attempt.
      const bool line_search_first = line_search_first_;
      options.line_search = line_search_first;
      report = solve_newton(*this, *linear_, du, options);
      if (!report.converged) {
        options.line_search = !line_search_first;
        du.setZero();
        NewtonReport retry = solve_newton(*this, *linear_, du, options);
        retry.abandoned_history = report.residual_history;
        retry.abandoned_line_search = line_search_first;
        retry.iterations += report.iterations;
        retry.linear_solves += report.linear_solves;
        retry.linear_iterations += report.linear_iterations;
        retry.factorizations += report.factorizations;
        retry.symbolic_analyses += report.symbolic_analyses;
        retry.seconds_analysis += report.seconds_analysis;
        retry.seconds_factorization += report.seconds_factorization;
        retry.seconds_solve += report.seconds_solve;
        report = std::move(retry);
        if (report.converged)
          line_search_first_ = !line_search_first;
      }
    }
    if (!report.converged && !trial_.last_rejection().empty())
      report.message += "; the last trial state Newton could not use: " + trial_.last_rejection();
    timings_.analysis += report.seconds_analysis;
    timings_.factorization += report.seconds_factorization;
    timings_.solve += report.seconds_solve;
    if (report.converged) {
      if (measure_compliance_ && !dynamic_ && report.factorizations > 0)
        load_compliance_ = compliance_under_load();
      commit(overlap_increment(step_.shared.expand(du)), dt);
      ramp_committed_ = ramp_end;
    }
    return report;
  }

  Energies energies() const override {
    const Energies e = particle_energies(scene_, dynamic_);
    return summed_over_ranks(e, *comm_);
  }
  FaceReactions reactions() const override { return reactions_; }
  std::vector<Vec3> prescribed_reactions() const override { return prescribed_reactions_; }
  std::string linear_solver() const override { return linear_->name(); }
  void measure_load_compliance() override { measure_compliance_ = true; }
  double load_compliance() const override { return load_compliance_; }
  Index active_nodes() const override { return step_.global_node_count; }
  Index unknowns() const override { return step_.global_dof_count; }
  ImplicitTimings timings() const override { return timings_; }
  Continuation continuation() const override { return {ramp_committed_, line_search_first_}; }
  void continue_from(const Continuation& c) override {
    ramp_committed_ = c.prescribed_fraction;
    line_search_first_ = c.line_search_first;
  }
  const SparseMatrix& last_tangent() const override { return tangent_.last(); }
  // The per-point trial state (the Newmark acceleration lives in the particles, which resize
  // it themselves); the map and the DOF numbering are rebuilt at the start of every step.
  void particles_changed() override { trial_.resize(); }

  // --- NonlinearSystem ----------------------------------------------------------------------
  // The owned unknowns, reduced where a platen's nodes share one (Newton's vectors hold those;
  // on one rank every unknown).
  Index size() const override {
    return step_.shared.any() ? step_.shared.size() : step_.owned_dof_count;
  }
  Index global_size() const override {
    return step_.shared.any() ? step_.shared.size() : step_.global_dof_count;
  }
  const Communicator* communicator() const override { return comm_; }

  // This rank's points on the unknowns it sees, then the ranks' shares added on the owners.
  bool residual(const Eigen::VectorXd& du, Eigen::VectorXd& r) override {
    Eigen::VectorXd mine;
    const bool admissible = !comm_->any(!assemble_share(
        whole_, whole_map_, overlap_increment(step_.shared.expand(du)), &mine, nullptr));
    if (admissible) {
      linear_->export_add(mine, r);
      step_.shared.condense(r);
    }
    return admissible;
  }

  const SparseMatrix& jacobian(const Eigen::VectorXd& du_owned) override {
    const Eigen::VectorXd du = overlap_increment(step_.shared.expand(du_owned));
    if (!trial_.matches(whole_, du) && !update_trial_state(whole_, whole_map_, du))
      throw NumericalError("material update failed while assembling the tangent");
    // Within a step the connectivity is fixed; a new step keeps the symbolic analysis when its
    // structure matches the last one built, whichever step or Newton attempt analysed it, and
    // the linear solver's numbering outlives the step (not so over several ranks).
    bool built = false;
    const SparseMatrix& K = share_tangent(whole_, whole_map_, built);
    if (built && (!linear_->keeps_analysis_across_steps() || !tangent_.same_structure_as_before()))
      ++pattern_generation_;
    return step_.shared.condense(K);
  }

  bool pattern_changed() const override { return pattern_generation_ != analysed_generation_; }
  void pattern_analysed() override { analysed_generation_ = pattern_generation_; }

  // The node and component of an unknown, and its diagonal stiffness against the largest: a
  // node that nothing stiff holds (a unit mistake, a body held nowhere) shows as a tiny ratio.
  std::string describe_unknown(Index reduced) const override {
    if (reduced < 0)
      return {};
    const Index i = step_.shared.first_of(reduced);
    const NodeLayout& layout = step_.dofs.layout();
    for (Index n = 0; n < step_.map.node_count(); ++n)
      for (int k = 0; k < layout.width(); ++k) {
        if (step_.dofs.dof(n, k) != i)
          continue;
        constexpr std::string_view kAxes = Axisymmetric ? "rz" : "xyz";
        const std::string what =
            k < Dim ? fmt::format("{} displacement", kAxes[at(k)]) : std::string("pore pressure");
        std::string text = fmt::format(": unknown {} is the {} of the grid node at [{:.4g}]", i,
                                       what, fmt::join(step_.map.nodes().position(n), ", "));
        if (const SparseMatrix& K = tangent_.last(); i < K.rows() && K.nonZeros() > 0) {
          const double largest = K.diagonal().cwiseAbs().maxCoeff();
          text += fmt::format(", whose diagonal stiffness is {:.3g} of the largest ({:.3g})",
                              K.coeff(i, i) / largest, largest);
        }
        return text;
      }
    return {};
  }

  // --- assembly by shares (ImplicitShareAssembly, for the tests; step() is one share) --
  void prepare(double lambda_end, double ramp_end, double dt) override {
    prepare_connectivity(lambda_end, ramp_end, dt);
    scale_by_prescribed_motion();
  }

  void prepare_connectivity(double lambda_end, double ramp_end, double dt) {
    const AddSeconds timer(timings_.step_setup);
    dt_ = dt;
    step_.prepare(scene_, {lambda_end, ramp_end, ramp_committed_, dt, dynamic_, gravity_ramped_},
                  material_young_);
    trial_.prepare(step_.map);
    ++step_count_;
    whole_ = {comm_->rank(), 0, scene_.particles.size()};
    // This rank's points reach every node of its step (and it assembles the ghost faces its
    // step holds): its map covers all of them, owned first, so local ids are the step's.
    std::vector<Index> nodes(at(step_.map.node_count()));
    std::iota(nodes.begin(), nodes.end(), Index{0});
    whole_map_ = DofMap(whole_.index, std::move(nodes), step_.dofs, step_.node.owner);
    if (whole_map_.owned_count() != step_.owned_dof_count)
      throw std::logic_error("the rank's DOF map does not number its owned unknowns first");
    if (step_.sharing_changed)
      ++pattern_generation_;
    if (step_.shared.any()) { // one rank: the reduced unknowns are their own global ids
      std::vector<Index> ids(at(size()));
      std::iota(ids.begin(), ids.end(), Index{0});
      linear_->set_unknowns(ids, size(), size());
    } else {
      linear_->set_unknowns(step_.dof_gid, step_.owned_dof_count, step_.global_dof_count);
    }
    if (linear_->uses_coordinates())
      linear_->set_coordinates(unknown_positions());
    if (whole_map_.overlap_count() != step_.dof_count) // every unknown sits on a point's stencil
      throw std::logic_error("the DOF map does not cover every unknown");
    if (linear_->uses_near_null_space())
      linear_->set_near_null_space(step_.shared.first_rows(
          near_null_space<Dim, Axisymmetric>(step_.map.nodes(), step_.dofs, step_.dof_count)));
  }

  const NodeDofs& global_dofs() const override { return step_.dofs; }

  std::vector<int> node_owners(std::span<const ParticleShare> shares) const override {
    std::vector<int> owner(at(step_.map.node_count()), -1);
    for (const ParticleShare& share : shares)
      for (Index p = share.begin; p < share.end; ++p)
        step_.map.for_each_node_of(p, [&](Index n, double, const V&) {
          int& o = owner[at(n)];
          if (o < 0 || share.index < o)
            o = share.index;
        });
    return owner;
  }

  std::vector<Index> touched_nodes(const ParticleShare& share,
                                   std::span<const int> node_owner) const override {
    // Marked per active node, then listed ascending: linear in the stencils, no sort.
    std::vector<char> touched(at(step_.map.node_count()), 0);
    for (Index p = share.begin; p < share.end; ++p)
      step_.map.for_each_node_of(p, [&](Index n, double, const V&) { touched[at(n)] = 1; });
    for (const auto& face : step_.ghost.faces())
      if (node_owner[at(Ghost::anchor(face))] == share.index)
        for (const Index n : face.nodes)
          touched[at(n)] = 1;
    std::vector<Index> nodes;
    for (std::size_t n = 0; n < touched.size(); ++n)
      if (touched[n])
        nodes.push_back(static_cast<Index>(n));
    return nodes;
  }

  DofMap dof_map(const ParticleShare& share, std::span<const int> node_owner) const override {
    return DofMap(share.index, touched_nodes(share, node_owner), step_.dofs, node_owner);
  }

  bool assemble_share(const ParticleShare& share, const DofMap& map,
                      const Eigen::VectorXd& du_overlap, Eigen::VectorXd* residual,
                      SparseMatrix* tangent) override {
    if (auto* f_bar = trial_.f_bar())
      f_bar->require_whole_cells(share);
    if (!trial_.matches(share, du_overlap) && !update_trial_state(share, map, du_overlap))
      return false;
    if (residual) {
      const AddSeconds timer(timings_.residual_assembly);
      balance().assemble(share, map, du_overlap, assembled_by(map), *residual);
    }
    if (tangent) {
      bool built = false;
      *tangent = share_tangent(share, map, built);
    }
    return true;
  }

private:
  /// The backend a step on one rank uses: the case's choice, or without one the size of the
  /// first step's system decides between direct and iterative. Non-associated flow, softening
  /// and F-bar make the tangent nonsymmetric: Cholesky cannot take it, LU can (the case reader
  /// refuses an explicit symmetric-only choice).
  LinearSolverKind serial_linear_solver_kind(bool symmetric) {
    // The coupled u-p system is indefinite: LU, whatever its size.
    if (scene_.spec.solver.linear_solver.empty() && step_.consolidation)
      return LinearSolverKind::Umfpack;
    if (scene_.spec.solver.linear_solver.empty())
      step_.map.update(scene_.grid, scene_.particles);
    return implicit_linear_solver(scene_.spec.solver.linear_solver, symmetric, Dim,
                                  Dim * step_.map.node_count());
  }

  /// The step's out-of-balance force and nodal increments (implicit_residual.hpp).
  ImplicitResidual<Dim, Shape, Axisymmetric> balance() const {
    return {step_, trial_, dynamic_, dt_};
  }

  /// f . K^-1 f / |f|^2 for the step's external load f (owned unknowns), with the factorisation
  /// Newton used last: its tangent is within the convergence tolerance of the converged state's.
  double compliance_under_load() {
    const AddSeconds timer(timings_.solve);
    Eigen::VectorXd f = step_.external.head(step_.owned_dof_count);
    step_.shared.condense(f);
    Eigen::VectorXd z;
    try {
      linear_->solve(f, z);
    } catch (const NumericalError&) {
      return std::numeric_limits<double>::quiet_NaN();
    }
    const double fz = comm_->sum(f.dot(z)), ff = comm_->sum(f.squaredNorm());
    return ff > 0 ? fz / ff : std::numeric_limits<double>::quiet_NaN();
  }

  /// The increment on every unknown this process sees, from Newton's owned unknowns (the
  /// ghosts' values come from their owners).
  Eigen::VectorXd overlap_increment(const Eigen::VectorXd& du) const {
    Eigen::VectorXd all;
    linear_->import_ghosts(du, all);
    return all;
  }

  /// Per unknown of the step, its node's position (MueLu repartitions coarse levels by them).
  Eigen::MatrixXd unknown_positions() const {
    Eigen::MatrixXd xyz(step_.dof_count, Dim);
    for (Index n = 0; n < step_.map.node_count(); ++n)
      for (int k = 0; k < step_.dofs.layout().width(); ++k)
        if (const Index dof = step_.dofs.dof(n, k); dof >= 0)
          xyz.row(dof) = step_.map.nodes().position(n).transpose();
    return step_.shared.first_rows(xyz);
  }

  /// Whether the map's share assembles the ghost-penalty face: the rank's own map every face
  /// of its step (the step holds only the faces this rank assembles: implicit_step_setup), a
  /// share of the rank's points those whose anchor node it owns.
  bool assembles(const DofMap& map, const typename Ghost::Face& face) const {
    return &map == &whole_map_ || map.owns_node(Ghost::anchor(face));
  }

  /// The ghost-penalty faces the map's share assembles, as a predicate.
  auto assembled_by(const DofMap& map) const {
    return [this, &map](const typename Ghost::Face& face) { return assembles(map, face); };
  }

  /// The share's tangent at the trial state (`built`: its structure built by this call).
  const SparseMatrix& share_tangent(const ParticleShare& share, const DofMap& map, bool& built) {
    const AddSeconds timer(timings_.tangent_assembly);
    const typename ImplicitTangent<Dim, Shape, Axisymmetric>::Step step{
        step_, trial_, scene_.particles, step_count_, dynamic_, dt_};
    return tangent_.of_share(step, share, map, assembled_by(map), built);
  }

  // A step driven by prescribed displacements (a footing pushed into weightless soil) has its
  // force level set by the reactions they cause, not by the loads: the residual of the
  // unknowns at zero increment, which the prescribed increment alone produces. Without this the
  // tolerance would be relative to the no-load fallback and ask for digits nobody needs.
  void scale_by_prescribed_motion() {
    const bool moving =
        comm_->any(std::any_of(step_.node.prescribed_du.begin(), step_.node.prescribed_du.end(),
                               [](const V& u) { return (u.array() != 0.0).any(); }));
    if (step_.global_dof_count == 0 || !moving)
      return;
    Eigen::VectorXd r;
    if (residual(Eigen::VectorXd::Zero(static_cast<Eigen::Index>(size())), r)) {
      const double largest = r.size() ? r.lpNorm<Eigen::Infinity>() : 0.0;
      step_.force_scale = std::max(step_.force_scale, comm_->max(largest));
    }
  }

  // The share's points at the trial increment (local ids of map).
  bool update_trial_state(const ParticleShare& share, const DofMap& map,
                          const Eigen::VectorXd& du) {
    const AddSeconds timer(timings_.material);
    const auto increments = balance();
    if (step_.consolidation)
      trial_.update_pore_pressure(
          share, step_.map, step_.node.pressure,
          [&](Index n) { return increments.pressure_increment(map, n, du); },
          step_.consolidation->flow);
    return trial_.update(
        share, step_.map, [&](Index n) { return increments.node_increment(map, n, du); }, du);
  }

  // Moves the points with the converged increment and stores their new state; the reactions
  // of the step.
  void commit(const Eigen::VectorXd& du, double dt) {
    if (!trial_.matches(whole_, du) && !update_trial_state(whole_, whole_map_, du))
      throw NumericalError("material update failed at the converged increment");
    const AddSeconds timer(timings_.commit);
    const auto balance_at = balance();
    std::vector<V> internal =
        commit_points(scene_, step_, trial_, balance_at, whole_map_, du, dt, dynamic_);
    balance_at.for_each_ghost_force(whole_map_, du, assembled_by(whole_map_),
                                    [&](Index n, int a, double f) { internal[at(n)][a] += f; });
    ImplicitReactions<Dim, Shape, Axisymmetric>(step_, scene_.spec.prescribed, *comm_)
        .compute(std::move(internal), reactions_, prescribed_reactions_);
  }

  Scene<Dim>& scene_;
  ImplicitStepSetup<Dim, Shape, Axisymmetric> step_; ///< connectivity, unknowns and loads
  const Communicator* comm_ = nullptr;               ///< the run's ranks (one in a serial run)
  std::unique_ptr<DistributedLinearSolver> linear_;
  std::vector<double> material_young_; ///< per material, for the ghost penalty's scale
  ImplicitTrialState<Dim, Shape, Axisymmetric> trial_;
  ParticleShare whole_; ///< this rank's points
  /// whole_'s DOF map: local ids are the step's unknowns (on one rank also their global ids).
  DofMap whole_map_;
  ImplicitTangent<Dim, Shape, Axisymmetric> tangent_;
  Index step_count_ = 0;           ///< steps prepared so far
  Index pattern_generation_ = 0;   ///< counts the tangent's distinct sparsity patterns so far
  Index analysed_generation_ = -1; ///< the pattern the linear solver was last analysed for
  FaceReactions reactions_{};
  ImplicitTimings timings_;
  bool dynamic_ = false;
  bool gravity_ramped_ = true;     ///< gravity follows the load factor (no geostatic stress)
  double ramp_committed_ = 0;      ///< prescribed-displacement fraction reached so far
  bool line_search_first_ = false; ///< the last step converged with the line search
  bool measure_compliance_ = false;
  double load_compliance_ = std::numeric_limits<double>::quiet_NaN();
  std::vector<Vec3> prescribed_reactions_;
  double round_off_force_ = 0; ///< eps * (largest p-wave modulus) * h
  double dt_ = 1;
};

template <int Dim, bool Axisymmetric> struct ImplicitIn {
  template <class Shape> using Solver = ImplicitSolverImpl<Dim, Shape, Axisymmetric>;
};

template <int Dim, bool Axisymmetric>
std::unique_ptr<ImplicitSolver> make_solver_for_shape(Scene<Dim>& scene,
                                                      double prescribed_fraction_reached) {
  return make_for_shape<ImplicitSolver, ImplicitIn<Dim, Axisymmetric>::template Solver>(
      scene.spec.solver.shape, scene, prescribed_fraction_reached);
}

} // namespace talus::implicit_detail
