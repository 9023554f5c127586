#pragma once
// CPDI, the convected particle domain interpolation (Sadeghirad, Brannon & Burghardt 2011):
// the particle domain is the deformed voxel itself, the parallelogram (parallelepiped)
//     x(xi) = x_p + J xi,   J = F diag(lp0),   xi in [-1, 1]^Dim,
// whose corners x_c = x_p + J xi_c are the voxels of post/voxels.hpp. The grid's hats S_i are
// interpolated multilinearly over the domain from their values at the corners and averaged
// exactly; with J constant over the domain,
//     w_i = 2^-Dim sum_c S_i(x_c),      grad w_i = J^-T 2^-Dim sum_c S_i(x_c) xi_c.
// A point whose voxel is a sheared parallelogram thus reaches the nodes its deformed domain
// covers, not a box: the weights are not tensor products, and the map keeps them per node
// (CpdiShape::Weights). Partition of unity and linear completeness hold exactly (the corners
// average to x_p). Like cpGIMP the domain is taken from F at the start of a step and held
// through it. Plane strain and 3D; in axisymmetry the hoop weighting of the domain by r is not
// part of the formula, and the reader refuses the combination.
#include "talus/core/errors.hpp"
#include "talus/core/types.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <fmt/format.h>

namespace talus {

struct CpdiShape {
  static constexpr int kWidth = 4;
  static constexpr bool kTensorProduct = false;
  static constexpr bool kDomainFollowsStretch = true;
  static constexpr const char* kName = "cpdi";
  /// The widest half-extent of the deformed voxel along an axis that four nodes cover.
  static constexpr double kMaxHalfWidthInCells = 1.0;

  template <int Dim> static constexpr int stencil_size() {
    int n = 1;
    for (int d = 0; d < Dim; ++d)
      n *= kWidth;
    return n;
  }

  /// A point's weights and gradients on the kWidth^Dim nodes from `start`, x fastest.
  template <int Dim> struct Weights {
    std::array<Index, Dim> start{};
    std::array<double, stencil_size<Dim>()> w{};
    std::array<Vec<Dim>, stencil_size<Dim>()> grad{};
  };

  /// The weights of point `p` at x (relative to the grid origin) with deformation F (grid axes)
  /// and initial voxel half-sizes lp0, on a grid of cell size h with `cells` cells per axis.
  /// Throws NumericalError if the deformed voxel is wider than the stencil reaches.
  template <int Dim>
  static void fill(Index p, const Vec<Dim>& x, const Mat<Dim>& F, const Vec<Dim>& lp0, double h,
                   const std::array<Index, Dim>& cells, Weights<Dim>& out) {
    const Mat<Dim> J = F * lp0.asDiagonal();
    const Vec<Dim> reach = J.cwiseAbs().rowwise().sum(); // half-extent of the bounding box
    for (int d = 0; d < Dim; ++d)
      if (!(reach[d] <= kMaxHalfWidthInCells * h))
        throw NumericalError(fmt::format(
            "particle {}'s cpdi domain is wider than its stencil reaches: half-extent {:g} along "
            "axis {}, more than {:g} cell size(s) of {:g}; split stretched points (a body's "
            "'split' block) or start with more particles per cell",
            p, reach[d], d, kMaxHalfWidthInCells, h));
    constexpr int kCorners = 1 << Dim;
    // The cell of each corner's hats (held inside the ghost layer: a corner on the far ghost
    // node takes the last cell with local coordinate 1), and the stencil's first node.
    std::array<std::array<Index, Dim>, kCorners> cell{};
    std::array<Vec<Dim>, kCorners> local{};
    std::array<Vec<Dim>, kCorners> xi{};
    for (int d = 0; d < Dim; ++d)
      out.start[d] = cells[d] + 1;
    for (int c = 0; c < kCorners; ++c) {
      for (int d = 0; d < Dim; ++d)
        xi[c][d] = (c >> d) & 1 ? 1.0 : -1.0;
      const Vec<Dim> xc = x + J * xi[c];
      for (int d = 0; d < Dim; ++d) {
        const double u = xc[d] / h;
        cell[c][d] = std::clamp<Index>(static_cast<Index>(std::floor(u)), -1, cells[d]);
        local[c][d] = u - static_cast<double>(cell[c][d]);
        out.start[d] = std::min(out.start[d], cell[c][d]);
      }
    }
    for (int d = 0; d < Dim; ++d)
      out.start[d] = std::min(out.start[d], cells[d] + 1 - (kWidth - 1));
    out.w.fill(0.0);
    std::array<Vec<Dim>, stencil_size<Dim>()> g;
    g.fill(Vec<Dim>::Zero());
    const double share = 1.0 / kCorners;
    for (int c = 0; c < kCorners; ++c)
      for (int n = 0; n < kCorners; ++n) { // the 2^Dim nodes of the corner's cell
        double S = share;
        int k = 0, stride = 1;
        for (int d = 0; d < Dim; ++d) {
          const bool upper = (n >> d) & 1;
          S *= upper ? local[c][d] : 1.0 - local[c][d];
          k += static_cast<int>(cell[c][d] + (upper ? 1 : 0) - out.start[d]) * stride;
          stride *= kWidth;
        }
        out.w[static_cast<std::size_t>(k)] += S;
        g[static_cast<std::size_t>(k)] += S * xi[c];
      }
    const Mat<Dim> J_inv_T = J.inverse().transpose();
    for (std::size_t k = 0; k < g.size(); ++k)
      out.grad[k] = J_inv_T * g[k];
  }
};

} // namespace talus
