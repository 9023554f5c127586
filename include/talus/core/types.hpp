#pragma once
// Basic numeric types shared by every Talus module.
#include <Eigen/Dense>

#include <cstdint>
#include <vector>

namespace talus {

using Index = std::int64_t;

template <int Dim> using Vec = Eigen::Matrix<double, Dim, 1>;
template <int Dim> using Mat = Eigen::Matrix<double, Dim, Dim>;
using Vec2 = Vec<2>;
using Vec3 = Vec<3>;
using Mat2 = Mat<2>;
using Mat3 = Mat<3>;

// Eigen fixed-size vectorisable types in std::vector need the aligned allocator before C++17;
// with C++17 aligned new this plain alias is enough.
template <class T> using Array = std::vector<T>;

} // namespace talus
