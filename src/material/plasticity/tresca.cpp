#include "talus/material/plasticity/tresca.hpp"

namespace talus {

Tresca::Tresca(const LameParameters& lame, double cohesion)
    : MohrCoulomb(lame, FrictionalStrengthParameters{cohesion, 0.0, 0.0, {}}) {}

} // namespace talus
