#pragma once
// What the case's boundaries impose on a grid node, decided from the node's lattice coordinates
// or position when a step asks, so that nothing is stored per node of the whole grid:
//   - the grid faces' conditions (which velocity components are held, and which face receives
//     each held component's reaction, and which platen moves a component), with the axis of an
//     axisymmetric run holding the radial component whatever x_min says;
//   - the prescribed-displacement boxes, which follow their displacement in whole cells.
#include "talus/grid/grid.hpp"
#include "talus/spec/case_spec.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace talus {

template <int Dim> class FaceConditions {
public:
  FaceConditions() = default;
  FaceConditions(const Grid<Dim>& grid, const BoundarySpec& faces, bool axisymmetric)
      : grid_(grid), faces_(faces), axisymmetric_(axisymmetric) {
    for (int face = 0; face < face_count(Dim); ++face)
      has_platen_ = has_platen_ || faces_[face] == FaceCondition::Platen;
  }

  /// Whether any face is a platen.
  bool has_platen() const { return has_platen_; }

  /// Bit d set: velocity component d of the node is held at zero (fixed or roller face).
  std::uint8_t held(const std::array<Index, Dim>& ijk) const {
    std::uint8_t mask = 0;
    for (int face = 0; face < face_count(Dim); ++face)
      if (on_face(ijk, face))
        mask |= mask_of(faces_[face], face_axis(face));
    mask &= static_cast<std::uint8_t>(~platen_mask(ijk));
    // Axisymmetry: a node on the axis (or behind it) moves along it only.
    if (axisymmetric_ && grid_.node_position(ijk)[0] <= 1e-9 * grid_.cell_size())
      mask |= 1u;
    return mask;
  }

  /// Per velocity component, the face whose condition holds it (-1 if none): the face that
  /// receives its reaction. At a corner each component goes to the face that constrains it,
  /// preferring the face normal to it.
  std::array<std::int8_t, Dim> reaction_faces(const std::array<Index, Dim>& ijk) const {
    std::array<std::int8_t, Dim> owner;
    owner.fill(-1);
    const std::uint8_t moved = platen_mask(ijk);
    for (int face = 0; face < face_count(Dim); ++face) {
      if (!on_face(ijk, face))
        continue;
      const int axis = face_axis(face);
      const std::uint8_t mask = mask_of(faces_[face], axis);
      for (int d = 0; d < Dim; ++d)
        if ((mask & (1u << d)) && !(moved & (1u << d)) && (owner[d] < 0 || d == axis))
          owner[d] = static_cast<std::int8_t>(face);
    }
    return owner;
  }

  /// The platen face that moves velocity component d of the node (the platen normal to axis d
  /// that the node lies on), or -1.
  int platen(const std::array<Index, Dim>& ijk, int d) const {
    if (!has_platen_)
      return -1;
    for (const int face : {2 * d, 2 * d + 1})
      if (faces_[face] == FaceCondition::Platen && on_face(ijk, face))
        return face;
    return -1;
  }

private:
  // The components a platen moves: at a platen's edge it wins over the face beside it (a
  // fixed side face would otherwise pin the platen's corner node).
  std::uint8_t platen_mask(const std::array<Index, Dim>& ijk) const {
    std::uint8_t mask = 0;
    for (int d = 0; d < Dim; ++d)
      if (platen(ijk, d) >= 0)
        mask |= static_cast<std::uint8_t>(1u << d);
    return mask;
  }

  // The boundary node and the ghost node behind it (inside the wall) share the condition.
  bool on_face(const std::array<Index, Dim>& ijk, int face) const {
    const int axis = face_axis(face);
    return face_is_upper(face) ? ijk[axis] >= grid_.cells(axis) : ijk[axis] <= 0;
  }
  static std::uint8_t mask_of(FaceCondition c, int normal_axis) {
    switch (c) {
    case FaceCondition::Free:
    case FaceCondition::Platen: // moves with the platen's own unknown
      return 0;
    case FaceCondition::Fixed:
      return static_cast<std::uint8_t>((1u << Dim) - 1);
    case FaceCondition::Roller:
      return static_cast<std::uint8_t>(1u << normal_axis);
    }
    return 0;
  }

  Grid<Dim> grid_;
  BoundarySpec faces_;
  bool axisymmetric_ = false;
  bool has_platen_ = false;
};

/// The prescribed-displacement boxes where they stand: each PrescribedSpec's box shifted by
/// the fraction `ramp` of its displacement (given components only), rounded to whole cells so
/// that it keeps holding the same number of node layers (a box one layer thick would otherwise
/// lose its nodes as soon as it moves); a rigid footing carries its box down with it.
template <int Dim> class PrescribedBoxes {
public:
  void place(const Grid<Dim>& grid, const std::vector<PrescribedSpec>& boxes, double ramp) {
    const double h = grid.cell_size();
    const double tol = 1e-9 * h;
    lo_.clear();
    hi_.clear();
    for (const PrescribedSpec& box : boxes) {
      Vec<Dim> shift = Vec<Dim>::Zero();
      for (int d = 0; d < Dim; ++d)
        if (box.displacement[static_cast<std::size_t>(d)])
          shift[d] = h * std::round(ramp * *box.displacement[static_cast<std::size_t>(d)] / h);
      lo_.push_back(head<Dim>(box.min) + shift - Vec<Dim>::Constant(tol));
      hi_.push_back(head<Dim>(box.max) + shift + Vec<Dim>::Constant(tol));
    }
  }

  /// The index of the first box that holds the node at x, -1 if none.
  std::int32_t region_of(const Vec<Dim>& x) const {
    for (std::size_t r = 0; r < lo_.size(); ++r)
      if ((x.array() >= lo_[r].array()).all() && (x.array() <= hi_[r].array()).all())
        return static_cast<std::int32_t>(r);
    return -1;
  }

private:
  std::vector<Vec<Dim>> lo_, hi_;
};

} // namespace talus
