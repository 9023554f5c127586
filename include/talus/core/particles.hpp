#pragma once
// Material points as a structure of arrays. Only the fields a scene needs are allocated: the
// always-present kinematic core below, plus optional blocks a later feature switches on.
#include "talus/core/types.hpp"

#include <string_view>

namespace talus {

template <int Dim> struct Particles {
  // --- always present -------------------------------------------------------------------------
  Array<Vec<Dim>> x;     ///< current position, m
  Array<Vec<Dim>> v;     ///< velocity, m/s
  Array<double> mass;    ///< kg (per unit thickness in 2D)
  Array<double> volume0; ///< initial volume, m^3 (per unit thickness in 2D)
  Array<double> volume;  ///< current volume = det(F) * volume0
  /// Deformation gradient, always 3x3: the materials see it whole. In plane strain the
  /// in-plane block moves and F33 = 1; grid_F(p) is the block along the grid's Dim axes.
  Array<Mat3> F;
  Array<Mat3> stress;             ///< Cauchy stress, Pa; full 3x3 so plane strain keeps sigma_zz
  Array<Vec<Dim>> half_size0;     ///< half the initial voxel edge lengths (GIMP half-width, voxels)
  Array<Vec<Dim>> x0;             ///< initial position (voxel reference point, colour patterns)
  Array<int> material;            ///< index into the scene's materials
  Array<int> body;                ///< index into the scene's bodies
  Array<Vec<Dim>> external_force; ///< point loads, N (per unit thickness); tractions: Scene

  // --- optional blocks (empty unless the scene needs them) -------------------------------------
  Array<Mat<Dim>> affine_velocity; ///< APIC's C_p = B_p D_p^-1 (transfer apic only)
  Array<Vec<Dim>> acceleration;    ///< m/s^2, Newmark state (implicit_dynamic only)
  /// Splitting (a body with a `split` block, core/splitting.hpp): F0^-1, the inverse of F when
  /// the point was made, so F^split = F F0^-1 needs no evolution of its own.
  Array<Mat3> split_origin_inverse;
  Array<int> split_generation; ///< splits in the point's ancestry (0: generated from a body)
  /// Pa, compression positive (a case with water only): the pore pressure u the point's total
  /// stress holds, sigma = sigma' - u I (scene/water_table.hpp).
  Array<double> pore_pressure;

  /// A distributed run's name for each point, the same on every rank and kept when the point
  /// moves between ranks: the point's index in the serial run (empty in a serial run).
  Array<std::int64_t> global_id;

  Index size() const { return static_cast<Index>(x.size()); }

  /// The block of F along the grid's axes (in-plane in 2D, all of it in 3D).
  Mat<Dim> grid_F(std::size_t p) const { return F[p].template topLeftCorner<Dim, Dim>(); }
  /// Advances F by the increment dF of the grid's axes (the out-of-plane F33 of plane strain
  /// stays 1).
  void advance_F(std::size_t p, const Mat<Dim>& dF) {
    F[p].template topLeftCorner<Dim, Dim>() = dF * grid_F(p);
  }

  /// f(name, array, fill) for every per-point array the points carry: the always-present ones,
  /// then the optional blocks that are allocated; `fill` is the value a new point starts from.
  /// The one list of the points' state: resizing, copying a point, checkpoints and moving
  /// points between ranks all walk it.
  template <class F> void for_each_field(F&& f) { visit_fields(*this, f, false); }
  template <class F> void for_each_field(F&& f) const { visit_fields(*this, f, false); }
  /// for_each_field that visits the optional blocks also when they are empty (a reader that
  /// finds out which ones its source holds).
  template <class F> void for_each_possible_field(F&& f) { visit_fields(*this, f, true); }
  template <class F> void for_each_possible_field(F&& f) const { visit_fields(*this, f, true); }
  /// Whether the field of that name is one of the optional blocks.
  static bool optional_field(std::string_view name) {
    for (const char* o : {"affine_velocity", "acceleration", "split_origin_inverse",
                          "split_generation", "pore_pressure", "global_id"})
      if (name == o)
        return true;
    return false;
  }

  void resize(Index n) {
    for_each_field([&](const char*, auto& a, const auto& fill) {
      a.resize(static_cast<std::size_t>(n), fill);
    });
  }

  /// Appends a copy of point p (every allocated field) and returns the new index.
  Index append_copy(Index p) {
    const auto from = static_cast<std::size_t>(p);
    const Index q = size();
    for_each_field([&](const char*, auto& a, const auto&) {
      const auto value = a[from]; // a copy: push_back may reallocate under a reference
      a.push_back(value);
    });
    return q;
  }

private:
  template <class Self, class F> static void visit_fields(Self& P, F& f, bool all) {
    f("x", P.x, Vec<Dim>::Zero().eval());
    f("v", P.v, Vec<Dim>::Zero().eval());
    f("mass", P.mass, 0.0);
    f("volume0", P.volume0, 0.0);
    f("volume", P.volume, 0.0);
    f("F", P.F, Mat3::Identity().eval());
    f("stress", P.stress, Mat3::Zero().eval());
    f("half_size0", P.half_size0, Vec<Dim>::Zero().eval());
    f("x0", P.x0, Vec<Dim>::Zero().eval());
    f("material", P.material, 0);
    f("body", P.body, 0);
    f("external_force", P.external_force, Vec<Dim>::Zero().eval());
    if (all || !P.affine_velocity.empty())
      f("affine_velocity", P.affine_velocity, Mat<Dim>::Zero().eval());
    if (all || !P.acceleration.empty())
      f("acceleration", P.acceleration, Vec<Dim>::Zero().eval());
    if (all || !P.split_origin_inverse.empty())
      f("split_origin_inverse", P.split_origin_inverse, Mat3::Identity().eval());
    if (all || !P.split_generation.empty())
      f("split_generation", P.split_generation, 0);
    if (all || !P.pore_pressure.empty())
      f("pore_pressure", P.pore_pressure, 0.0);
    if (all || !P.global_id.empty())
      f("global_id", P.global_id, std::int64_t{-1});
  }
};

} // namespace talus
