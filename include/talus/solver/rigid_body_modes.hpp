#pragma once
// The rigid-body motions of the grid's unknowns: the near-null space of the elastic tangent that
// algebraic multigrid (MueLu's smoothed aggregation) builds its coarse spaces from. Without them
// it interpolates constants per unknown only, which for elasticity leaves the rotations to the
// smoother on every level (Vanek, Mandel & Brezina 1996). Plane strain: two translations and
// the in-plane rotation; 3D: three translations and three rotations; axisymmetry: the axial
// translation only (a radial translation stretches the hoops, a rotation leaves the meridian
// plane). Rotations are taken about the unknowns' centroid so that no mode dwarfs the others.
// A layout's other fields (a pore pressure) add a constant per component: the null space of
// their flux operator, which aggregation would otherwise interpolate by nothing at all.
#include "talus/grid/active_nodes.hpp"
#include "talus/linalg/node_layout.hpp"

#include <Eigen/Core>

namespace talus {

/// One column per mode, one row per unknown; `dofs` numbers the unknowns of the active nodes,
/// of which the modes move the displacement's (the rows of other fields stay zero).
template <int Dim, bool Axisymmetric>
Eigen::MatrixXd rigid_body_modes(const ActiveNodes<Dim>& nodes, const NodeDofs& dofs,
                                 Index unknowns) {
  constexpr int kRotations = Axisymmetric ? 0 : Dim == 2 ? 1 : 3;
  constexpr int kTranslations = Axisymmetric ? 1 : Dim;
  Eigen::MatrixXd modes = Eigen::MatrixXd::Zero(unknowns, kTranslations + kRotations);
  if (unknowns == 0)
    return modes;
  auto dof = [&](Index n, int a) { return dofs.dof(n, NodeLayout::kDisplacement, a); };
  Vec<Dim> centre = Vec<Dim>::Zero();
  Index counted = 0;
  for (Index n = 0; n < nodes.size(); ++n)
    for (int a = 0; a < Dim; ++a)
      if (dof(n, a) >= 0) {
        centre += nodes.position(n);
        ++counted;
      }
  centre /= static_cast<double>(counted);
  for (Index n = 0; n < nodes.size(); ++n) {
    const Vec<Dim> x = nodes.position(n) - centre;
    for (int a = 0; a < Dim; ++a) {
      const Index d = dof(n, a);
      if (d < 0)
        continue;
      if constexpr (Axisymmetric) {
        modes(d, 0) = a == 1 ? 1.0 : 0.0;
      } else {
        modes(d, a) = 1.0;
        if constexpr (Dim == 2) {
          modes(d, 2) = a == 0 ? -x[1] : x[0]; // about z
        } else {
          // Rotation about axis r moves component a by (e_r x x)_a: with (r, b, c) cyclic,
          // (e_r x x)_b = -x_c and (e_r x x)_c = x_b.
          for (int r = 0; r < 3; ++r) {
            const int b = (r + 1) % 3, c = (r + 2) % 3;
            modes(d, Dim + r) = a == b ? -x[c] : a == c ? x[b] : 0.0;
          }
        }
      }
    }
  }
  return modes;
}

/// The near-null space of a layout's unknowns, the solver's view of the block structure: the
/// displacement's rigid-body modes, then for each component of every other field a column of
/// ones on that component's unknowns. A displacement-only layout gives rigid_body_modes.
template <int Dim, bool Axisymmetric>
Eigen::MatrixXd near_null_space(const ActiveNodes<Dim>& nodes, const NodeDofs& dofs,
                                Index unknowns) {
  const Eigen::MatrixXd rigid = rigid_body_modes<Dim, Axisymmetric>(nodes, dofs, unknowns);
  const NodeLayout& layout = dofs.layout();
  const int constants = layout.width() - layout.components(NodeLayout::kDisplacement);
  if (constants == 0)
    return rigid;
  Eigen::MatrixXd modes = Eigen::MatrixXd::Zero(unknowns, rigid.cols() + constants);
  modes.leftCols(rigid.cols()) = rigid;
  Eigen::Index column = rigid.cols();
  for (int field = 0; field < layout.fields(); ++field) {
    if (field == NodeLayout::kDisplacement)
      continue;
    for (int c = 0; c < layout.components(field); ++c, ++column)
      for (Index n = 0; n < nodes.size(); ++n)
        if (const Index d = dofs.dof(n, field, c); d >= 0)
          modes(d, column) = 1.0;
  }
  return modes;
}

} // namespace talus
