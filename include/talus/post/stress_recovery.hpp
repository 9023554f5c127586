#pragma once
// Stress recovery from the reference talk (Andersen 2013): particle stresses in MPM can be
// erratic (a bent beam's shear stress at the points is a mess), yet their mass-weighted
// projection to the grid is physically right. Two post-processing fields, computed on output
// frames only:
//   grid-node stress          sigma_i = sum_p sigma_p Phi_ip m_p / m_i,  m_i = sum_p Phi_ip m_p
//   smoothed particle stress  sigma_p^s = sum_i sigma_i Phi_ip
// Phi_ip are the run's own shape-function kernels (linear hats or uGIMP) at the current
// positions.
#include "talus/core/particles.hpp"
#include "talus/grid/grid.hpp"
#include "talus/spec/case_spec.hpp"

#include <array>
#include <memory>
#include <vector>

namespace talus {

/// A symmetric stress by its six components in XDMF Tensor6 order: xx, xy, xz, yy, yz, zz (the
/// order of the stress datasets in run.h5; six sums instead of nine).
using SymmetricStress = Eigen::Matrix<double, 6, 1>;

template <int Dim> struct RecoveredStress {
  Grid<Dim> grid; ///< the background grid
  /// The box of nodes the node arrays cover, the smallest that holds every point's stencil:
  /// its first node's lattice coordinates (ghosts at -1) and its nodes per direction. The
  /// arrays follow the material, not the grid.
  std::array<Index, Dim> first{}, count{};
  std::vector<double> node_mass;          ///< m_i per node of the box (x fastest), kg
  Array<SymmetricStress> node_stress;     ///< sigma_i per node of the box, Pa; zero where m_i = 0
  Array<SymmetricStress> smoothed_stress; ///< sigma_p^s per particle, Pa
  /// The position in the node arrays of the node at lattice coordinates ijk (inside the box).
  std::size_t box_index(const std::array<Index, Dim>& ijk) const {
    Index id = 0;
    for (int d = Dim - 1; d >= 0; --d)
      id = id * count[d] + (ijk[d] - first[d]);
    return static_cast<std::size_t>(id);
  }
};

/// Computes RecoveredStress for successive frames of one run. It keeps its arrays between
/// calls: a run allocates them once, not once per frame.
template <int Dim> class StressRecovery {
public:
  StressRecovery(const Grid<Dim>& grid, ShapeFunction shape);
  ~StressRecovery();
  StressRecovery(StressRecovery&&) noexcept;
  StressRecovery& operator=(StressRecovery&&) noexcept;
  /// Projects the particle stresses to the grid and back. Throws NumericalError if a particle
  /// lies outside the grid. The result stays valid until the next call.
  const RecoveredStress<Dim>& recover(const Particles<Dim>& particles);

  class Impl; ///< the work for one shape function (src/post/stress_recovery.cpp)

private:
  std::unique_ptr<Impl> impl_;
};

} // namespace talus
