#pragma once
// A material point's block of the implicit tangent over the nodes of its stencil,
//     K_p = V0 B^T A B,
// with B mapping the nodal increments to the step components (step_tangent.hpp; row Dim a + b:
// du_a/dx_b, and in axisymmetry the hoop row u_r N / r_n) and A = dG/d(dF) the point's step
// tangent. B has one gradient per column (rows Dim c .. Dim c + Dim - 1 of column (j, c)) and
// per row of B^T, so both products take Dim terms per entry instead of Dim^2; the hoop row adds
// one term to the radial columns and rows.
#include "step_tangent.hpp"

#include <Eigen/Core>
#include <type_traits>

namespace talus {

/// The point block's matrix type: fixed size while it fits Eigen's stack limit; the 64-node
/// stencils of 3D (cpGIMP, CPDI, cubic splines: 192 x 192) keep it on the heap.
template <int kDofs>
using PointStiffness = std::conditional_t<(kDofs * kDofs * sizeof(double) > 64 * 1024),
                                          Eigen::MatrixXd, Eigen::Matrix<double, kDofs, kDofs>>;

/// K += V0 B^T A B for a stencil of kNodes nodes: grads their weight gradients, hoop their
/// N / r_n (axisymmetry; unused otherwise). K must be Dim kNodes square. Adding lets the points
/// that share a stencil sum into one block before it goes into the sparse matrix.
template <int Dim, bool Axisymmetric, int kNodes, class Matrix>
void add_point_stiffness(const Eigen::Matrix<double, Dim, kNodes>& grads,
                         const Eigen::Matrix<double, 1, kNodes>& hoop,
                         const StepTangent<Dim, Axisymmetric>& A, double V0, Matrix& K) {
  using Components = StepComponents<Dim, Axisymmetric>;
  constexpr int kDofs = Dim * kNodes;
  Eigen::Matrix<double, Components::kCount, kDofs> AB;
  for (int j = 0; j < kNodes; ++j)
    for (int c = 0; c < Dim; ++c) {
      AB.col(Dim * j + c) = A.template middleCols<Dim>(Dim * c) * grads.col(j);
      if constexpr (Axisymmetric)
        if (c == 0)
          AB.col(Dim * j) += A.col(Components::kHoop) * hoop[j];
    }
  for (int col = 0; col < kDofs; ++col)
    for (int i = 0; i < kNodes; ++i)
      for (int a = 0; a < Dim; ++a) {
        double v = grads.col(i).dot(AB.col(col).template segment<Dim>(Dim * a));
        if constexpr (Axisymmetric)
          if (a == 0)
            v += hoop[i] * AB(Components::kHoop, col);
        K(Dim * i + a, col) += V0 * v;
      }
}

} // namespace talus
