#pragma once
// Tresca plasticity: the exact hexagonal prism sigma_1 - sigma_3 = 2 c (tension positive,
// sigma_1 >= sigma_2 >= sigma_3), with c the undrained shear strength s_u: a uniaxial test yields
// at |sigma| = 2 c, pure shear at tau = c. It is Mohr-Coulomb with phi = psi = 0, so the return
// (to one plane, or to the compression / extension edge where two planes meet) and its exact
// consistent tangent are those of mohr_coulomb.hpp; the prism has no apex.
#include "talus/material/plasticity/mohr_coulomb.hpp"

namespace talus {

class Tresca final : public MohrCoulomb {
public:
  /// Throws InputError unless cohesion > 0.
  Tresca(const LameParameters& lame, double cohesion);
  const char* name() const override { return "Tresca"; }
};

} // namespace talus
