#pragma once
#include "talus/material/principal_space.hpp"

namespace talus {

/// Kirchhoff stress tau = J sigma and its derivative with respect to the deformation
/// gradient, flattened row-major: dtau_dF(3*i + j, 3*k + l) = d tau_ij / d F_kl.
struct StressTangent {
  Mat3 kirchhoff = Mat3::Zero();
  Mat9 dtau_dF = Mat9::Zero();
};

} // namespace talus
