#pragma once
// Material points as a structure of arrays. Only the fields a scene needs are allocated: the
// always-present kinematic core below, plus optional blocks a later feature switches on.
#include "talus/core/types.hpp"

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

  Index size() const { return static_cast<Index>(x.size()); }

  /// The block of F along the grid's axes (in-plane in 2D, all of it in 3D).
  Mat<Dim> grid_F(std::size_t p) const { return F[p].template topLeftCorner<Dim, Dim>(); }
  /// Advances F by the increment dF of the grid's axes (the out-of-plane F33 of plane strain
  /// stays 1).
  void advance_F(std::size_t p, const Mat<Dim>& dF) {
    F[p].template topLeftCorner<Dim, Dim>() = dF * grid_F(p);
  }

  void resize(Index n) {
    const auto s = static_cast<std::size_t>(n);
    x.resize(s);
    v.resize(s);
    mass.resize(s);
    volume0.resize(s);
    volume.resize(s);
    F.resize(s, Mat3::Identity());
    stress.resize(s, Mat3::Zero());
    half_size0.resize(s);
    x0.resize(s);
    material.resize(s);
    body.resize(s);
    external_force.resize(s, Vec<Dim>::Zero());
    if (!affine_velocity.empty())
      affine_velocity.resize(s, Mat<Dim>::Zero());
    if (!acceleration.empty())
      acceleration.resize(s, Vec<Dim>::Zero());
    if (!split_origin_inverse.empty())
      split_origin_inverse.resize(s, Mat3::Identity());
    if (!split_generation.empty())
      split_generation.resize(s, 0);
  }

  /// Appends a copy of point p (every allocated field) and returns the new index.
  Index append_copy(Index p) {
    const auto from = static_cast<std::size_t>(p);
    const Index q = size();
    resize(q + 1);
    const auto to = static_cast<std::size_t>(q);
    x[to] = x[from];
    v[to] = v[from];
    mass[to] = mass[from];
    volume0[to] = volume0[from];
    volume[to] = volume[from];
    F[to] = F[from];
    stress[to] = stress[from];
    half_size0[to] = half_size0[from];
    x0[to] = x0[from];
    material[to] = material[from];
    body[to] = body[from];
    external_force[to] = external_force[from];
    if (!affine_velocity.empty())
      affine_velocity[to] = affine_velocity[from];
    if (!acceleration.empty())
      acceleration[to] = acceleration[from];
    if (!split_origin_inverse.empty())
      split_origin_inverse[to] = split_origin_inverse[from];
    if (!split_generation.empty())
      split_generation[to] = split_generation[from];
    return q;
  }
};

} // namespace talus
