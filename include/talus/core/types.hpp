#pragma once
// Basic numeric types shared by every Talus module.
#include <Eigen/Dense>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace talus {

using Index = std::int64_t;

/// An index (Index or int) as a position in a std::vector.
constexpr std::size_t at(Index i) {
  return static_cast<std::size_t>(i);
}

template <int Dim> using Vec = Eigen::Matrix<double, Dim, 1>;
template <int Dim> using Mat = Eigen::Matrix<double, Dim, Dim>;
using Vec2 = Vec<2>;
using Vec3 = Vec<3>;
using Mat2 = Mat<2>;
using Mat3 = Mat<3>;

/// The first Dim components of a case's 3-vector (a 2D case keeps z = 0).
template <int Dim> Vec<Dim> head(const Vec3& v) {
  // Element by element: Eigen's head<2>() of a Vec3 is one unaligned SSE load, which GCC 12's
  // -Warray-bounds takes for a read past the vector.
  Vec<Dim> out;
  for (int d = 0; d < Dim; ++d)
    out[d] = v[d];
  return out;
}
/// A Dim-vector as a case's 3-vector (z = 0 in 2D).
template <int Dim> Vec3 padded(const Vec<Dim>& v) {
  Vec3 out = Vec3::Zero();
  out.template head<Dim>() = v;
  return out;
}

/// A Dim x Dim matrix of the grid's axes embedded in 3x3, the identity elsewhere (plane strain:
/// F33 = 1).
template <int Dim> Mat3 embedded(const Mat<Dim>& a) {
  Mat3 out = Mat3::Identity();
  out.template topLeftCorner<Dim, Dim>() = a;
  return out;
}

// Eigen fixed-size vectorisable types in std::vector need the aligned allocator before C++17;
// with C++17 aligned new this plain alias is enough.
template <class T> using Array = std::vector<T>;

} // namespace talus
