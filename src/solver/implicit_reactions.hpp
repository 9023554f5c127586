#pragma once
// The reactions of a converged implicit step: the internal force that the constrained
// components of the nodes carry beyond the loads, summed per reaction face (the faces that
// hold a component) and per prescribed box (the components it prescribes), over all ranks.
#include "implicit_step_setup.hpp"
#include "talus/solver/rank_sums.hpp"

#include <vector>

namespace talus {

template <int Dim, class Shape, bool Axisymmetric> class ImplicitReactions {
  using V = Vec<Dim>;

public:
  ImplicitReactions(const ImplicitStepSetup<Dim, Shape, Axisymmetric>& step,
                    const std::vector<PrescribedSpec>& prescribed, const Communicator& comm)
      : step_(step), prescribed_(prescribed), comm_(comm) {}

  /// Whether component a of node n follows its prescribed box.
  bool is_prescribed(Index n, int a) const {
    const std::int32_t region = step_.node.region[at(n)];
    return region >= 0 && prescribed_[at(region)].displacement[at(a)].has_value();
  }

  /// From `internal`, per node this rank's points' internal forces (ghost-penalty forces of the
  /// faces it assembles included): the face reactions and one per prescribed box.
  void compute(std::vector<V> internal, FaceReactions& faces, std::vector<Vec3>& boxes) const {
    // The loads on a node are whole on every rank holding it: its owner subtracts them; the
    // internal forces are each rank's own, summed over the ranks below.
    for (Index n = 0; n < step_.map.node_count(); ++n)
      if (step_.node.owner[at(n)] == step_.rank())
        internal[at(n)] -= step_.node.load[at(n)];
    boxes.assign(prescribed_.size(), Vec3::Zero());
    for (Index n = 0; n < step_.map.node_count(); ++n) {
      const std::int32_t region = step_.node.region[at(n)];
      if (region < 0)
        continue;
      for (int a = 0; a < Dim; ++a)
        if (is_prescribed(n, a))
          boxes[at(region)][a] += internal[at(n)][a];
    }
    for (auto& r : faces)
      r.setZero();
    for (Index n = 0; n < step_.map.node_count(); ++n)
      for (int a = 0; a < Dim; ++a)
        if (const int face = step_.node.reaction_face[at(n)][at(a)];
            face >= 0 && !is_prescribed(n, a))
          faces[static_cast<std::size_t>(face)][a] += internal[at(n)][a];
    faces = summed_over_ranks(faces, comm_);
    boxes = summed_over_ranks(std::span<const Vec3>(boxes), comm_);
  }

private:
  const ImplicitStepSetup<Dim, Shape, Axisymmetric>& step_;
  const std::vector<PrescribedSpec>& prescribed_;
  const Communicator& comm_;
};

} // namespace talus
