#pragma once
// A material point's stencil at the start of an implicit step, gathered into fixed-size
// arrays for the dense point terms: its nodes, their weights N and weight gradients, and in
// axisymmetry N / r_n.
#include "talus/grid/particle_grid_map.hpp"

#include <Eigen/Core>

#include <array>

namespace talus {

template <int Dim, class Shape> struct PointStencil {
  static constexpr int kNodes = ParticleGridMap<Dim, Shape>::kStencilSize;
  std::array<Index, kNodes> nodes{};
  Eigen::Matrix<double, 1, kNodes> weights, hoop;
  Eigen::Matrix<double, Dim, kNodes> grads;

  /// Point p's stencil on map; radius: its r_n (axisymmetry), else unused.
  PointStencil(const ParticleGridMap<Dim, Shape>& map, Index p, double radius) {
    int k = 0;
    map.for_each_node_of(p, [&](Index n, double w, const Vec<Dim>& grad) {
      nodes[at(k)] = n;
      weights[k] = w;
      hoop[k] = w / radius;
      grads.col(k++) = grad;
    });
  }
};

} // namespace talus
