#pragma once
// The consistent tangent of an implicit step, assembled per share of the points on the share's
// DofMap: per group of points with one stencil the sum of their dense blocks
// K_p = V0 B^T A B (point_stiffness.hpp), the F-bar cell coupling, the ghost-penalty face
// blocks per component, and the Newmark mass of the owned unknowns. The sparsity structure is
// built at a share's first assembly in a step and then only refilled.
#include "implicit_step_setup.hpp"
#include "implicit_trial_state.hpp"
#include "point_stiffness.hpp"
#include "talus/core/parallel.hpp"
#include "talus/linalg/dof_map.hpp"
#include "talus/linalg/lattice_assembler.hpp"
#include "water_stiffness.hpp"

#include <algorithm>
#include <array>
#include <span>
#include <vector>

namespace talus {

template <int Dim, class Shape, bool Axisymmetric> class ImplicitTangent {
  using V = Vec<Dim>;
  using Ghost = GhostPenalty<Dim>;
  using Setup = ImplicitStepSetup<Dim, Shape, Axisymmetric>;
  using Trial = ImplicitTrialState<Dim, Shape, Axisymmetric>;

public:
  /// The step the tangent is assembled in: its setup, the trial state, the step's number (a
  /// new number builds the structure anew) and, for Newmark, its length.
  struct Step {
    const Setup& setup;
    Trial& trial;
    const Particles<Dim>& points;
    Index number = 0;
    bool dynamic = false;
    double dt = 1;
  };

  /// The share's tangent at the trial state; `assembles(face)`: whether the share assembles a
  /// ghost-penalty face. `built` tells whether its structure was built by this call.
  template <class Assembles>
  const SparseMatrix& of_share(const Step& step, const ParticleShare& share, const DofMap& map,
                               Assembles&& assembles, bool& built) {
    if (shares_.size() <= at(share.index))
      shares_.resize(at(share.index) + 1);
    ShareTangent& t = shares_[at(share.index)];
    built = t.step != step.number || t.begin != share.begin || t.end != share.end ||
            t.assembler.size() != map.overlap_count();
    if (built) {
      build_structure(step, share, map, assembles, t.assembler);
      t.step = step.number;
      t.begin = share.begin;
      t.end = share.end;
    } else {
      t.assembler.begin();
    }
    assemble(step, share, map, assembles, t.assembler);
    return t.assembler.finish();
  }

  /// The first share's last tangent (the rank's own), or an empty matrix before any.
  const SparseMatrix& last() const {
    static const SparseMatrix kNone;
    return shares_.empty() ? kNone : shares_[0].assembler.finish();
  }
  /// Whether the rank's last structure repeats the one built before it.
  bool same_structure_as_before() const {
    return !shares_.empty() && shares_[0].assembler.same_structure_as_before();
  }

private:
  /// The sets of nodes the share's tangent couples: each distinct point stencil, the nodes of
  /// each F-bar cell and of each ghost-penalty face the share assembles.
  template <class Assembles>
  void build_structure(const Step& step, const ParticleShare& share, const DofMap& map,
                       Assembles& assembles, LatticeAssembler<Dim>& tangent) {
    group_by_stencil(step, share);
    const auto& map_of_step = step.setup.map;
    const auto cliques = [&](auto&& f) {
      for (std::size_t g = 0; g + 1 < group_begin_.size(); ++g) {
        const auto nodes = map_of_step.stencil_nodes(point_of_group(static_cast<Index>(g)));
        f(std::span<const Index>(nodes));
      }
      if (auto* f_bar = step.trial.f_bar())
        f_bar->for_each_cell_nodes(share, map_of_step, f);
      if (step.setup.consolidation)
        step.setup.projection.for_each_cell_nodes(share, map_of_step, f);
      for (const auto& face : step.setup.ghost.faces())
        if (assembles(face))
          f(std::span<const Index>(face.nodes));
    };
    tangent.build(
        map_of_step.nodes(), map.layout(), map.overlap_count(),
        [&](Index n, int k) { return map.overlap_dof_at(n, k); }, cliques);
  }

  /// The share's points grouped by their stencil (the same start, so the same nodes), groups
  /// in the order of their start node, points ascending within a group.
  void group_by_stencil(const Step& step, const ParticleShare& share) {
    const auto& map = step.setup.map;
    stencil_points_.clear();
    for (Index p = share.begin; p < share.end; ++p)
      stencil_points_.push_back({map.nodes().grid().node_id(map.stencil(p).start), p});
    std::sort(stencil_points_.begin(), stencil_points_.end());
    group_begin_.clear();
    for (std::size_t i = 0; i < stencil_points_.size(); ++i)
      if (i == 0 || stencil_points_[i][0] != stencil_points_[i - 1][0])
        group_begin_.push_back(static_cast<Index>(i));
    group_begin_.push_back(static_cast<Index>(stencil_points_.size()));
  }

  /// The first point of group g (any of its points has the group's stencil).
  Index point_of_group(Index g) const { return stencil_points_[at(group_begin_[at(g)])][1]; }

  // The groups' blocks are computed in parallel a chunk at a time and added to the sparse
  // matrix in group order: one lattice lookup per group, and sums that do not depend on the
  // thread count.
  template <class Assembles>
  void assemble(const Step& step, const ParticleShare& share, const DofMap& map,
                Assembles& assembles, LatticeAssembler<Dim>& tangent) {
    constexpr int kNodes = ParticleGridMap<Dim, Shape>::kStencilSize;
    constexpr int kDofs = Dim * kNodes;
    // About 2 MB of blocks per chunk: 800 groups in 2D GIMP, 40 in 3D, 16 for 64-node stencils.
    constexpr Index kChunk = std::max<Index>(16, (2 << 20) / (kDofs * kDofs * sizeof(double)));
    const auto& P = step.points;
    const auto& map_of_step = step.setup.map;
    Trial& trial = step.trial;
    const Index groups = static_cast<Index>(group_begin_.size()) - 1;
    group_blocks_.resize(at(std::min(groups, kChunk)));
    for (auto& K : group_blocks_)
      K.resize(kDofs, kDofs); // the heap-stored 3D blocks; a no-op for fixed sizes
    const bool consolidation = step.setup.consolidation.has_value();
    if (consolidation)
      biot_blocks_.resize(group_blocks_.size());
    for (Index first = 0; first < groups; first += kChunk) {
      const Index count = std::min(kChunk, groups - first);
      parallel_for(
          count,
          [&](Index i) {
            PointStiffness<kDofs>& K = group_blocks_[at(i)];
            K.setZero();
            if (consolidation)
              biot_blocks_[at(i)].set_zero();
            Eigen::Matrix<double, Dim, kNodes> grads;
            Eigen::Matrix<double, 1, kNodes> weights, hoop; // N, N / r_n (axisymmetry)
            for (Index e = group_begin_[at(first + i)]; e < group_begin_[at(first + i + 1)]; ++e) {
              const Index p = stencil_points_[at(e)][1];
              const auto s = at(p);
              int k = 0;
              map_of_step.for_each_node_of(p, [&](Index, double w, const V& grad) {
                if constexpr (Axisymmetric)
                  hoop[k] = w / trial.radius_n(s);
                weights[k] = w;
                grads.col(k++) = grad;
              });
              add_point_stiffness<Dim, Axisymmetric, kNodes>(
                  grads, hoop, trial.point_step_tangent(s), P.volume0[s], K);
              if (const V water = trial.water_force(s); !water.isZero(0.0))
                add_water_stiffness<Dim, Axisymmetric, kNodes>(weights, grads, hoop,
                                                               trial.step_gradient(s), water, K);
              if (consolidation)
                biot_point(step, p, weights, grads, hoop)
                    .add_blocks(biot_blocks_[at(i)].up, biot_blocks_[at(i)].pu,
                                biot_blocks_[at(i)].pp);
            }
          },
          8);
      for (Index i = 0; i < count; ++i) {
        const auto nodes = map_of_step.stencil_nodes(point_of_group(first + i));
        tangent.add_block(nodes, group_blocks_[at(i)]);
        if (consolidation) {
          const BiotBlocks& b = biot_blocks_[at(i)];
          const int p = step.setup.pressure_field;
          tangent.add_coupling_block(nodes, NodeLayout::kDisplacement, p, b.up);
          tangent.add_coupling_block(nodes, p, NodeLayout::kDisplacement, b.pu);
          tangent.add_block(nodes, b.pp, p);
        }
      }
    }
    if (auto* f_bar = trial.f_bar())
      f_bar->add_coupling(
          share, map_of_step, P, [&](Index q) { return trial.step_gradient(at(q)); }, tangent);
    if (consolidation)
      step.setup.projection.add_tangent(share, map_of_step, P,
                                        step.setup.consolidation->pressure_unit,
                                        step.setup.pressure_field, tangent);
    const auto& G = Ghost::face_matrix();
    for (const auto& face : step.setup.ghost.faces()) {
      if (!assembles(face))
        continue;
      const typename Ghost::FaceMatrix K_face = face.stiffness * G;
      for (int a = 0; a < Dim; ++a)
        tangent.add_component_block(face.nodes, a, K_face);
    }
    if (step.dynamic) {
      const auto& gids = map.overlap_gids();
      for (Index l = 0; l < map.owned_count(); ++l)
        tangent.add_diagonal(l, 4.0 * step.setup.dof_mass[at(gids[at(l)])] / (step.dt * step.dt));
    }
  }

  /// Point p's mass balance at the trial state (consolidation.hpp), on its stencil's values.
  template <int kNodes>
  static BiotPoint<Dim, Axisymmetric, kNodes>
  biot_point(const Step& step, Index p, const Eigen::Matrix<double, 1, kNodes>& weights,
             const Eigen::Matrix<double, Dim, kNodes>& grads,
             const Eigen::Matrix<double, 1, kNodes>& hoop) {
    const auto s = at(p);
    const Consolidation<Dim>& c = *step.setup.consolidation;
    return {weights,
            grads,
            hoop,
            step.trial.step_gradient(s),
            c.flow[at(step.trial.material(s))],
            step.trial.volume_n(s),
            c.flow_time,
            c.pressure_unit,
            step.trial.pressure_increment(s),
            step.trial.pressure_gradient(s),
            c.gravity_head};
  }

  /// A group's consolidation blocks: displacement rows by pressure columns, the transpose's
  /// shape, and pressure by pressure (consolidation.hpp).
  struct BiotBlocks {
    static constexpr int kNodes = ParticleGridMap<Dim, Shape>::kStencilSize;
    Eigen::Matrix<double, Dim * kNodes, kNodes> up;
    Eigen::Matrix<double, kNodes, Dim * kNodes> pu;
    Eigen::Matrix<double, kNodes, kNodes> pp;
    void set_zero() {
      up.setZero();
      pu.setZero();
      pp.setZero();
    }
  };

  /// A share's tangent assembler and the step and points its structure was built for.
  struct ShareTangent {
    LatticeAssembler<Dim> assembler;
    Index step = -1, begin = -1, end = -1;
  };
  std::vector<ShareTangent> shares_; ///< per share index (the rank's own: [0])
  /// (stencil start, point) of the share's points, sorted: the points grouped by stencil.
  std::vector<std::array<Index, 2>> stencil_points_;
  std::vector<Index> group_begin_; ///< where each group starts in stencil_points_, and the end
  /// One chunk of groups' summed blocks.
  std::vector<PointStiffness<Dim * ParticleGridMap<Dim, Shape>::kStencilSize>> group_blocks_;
  std::vector<BiotBlocks> biot_blocks_; ///< the chunk's consolidation blocks (consolidation only)
};

} // namespace talus
