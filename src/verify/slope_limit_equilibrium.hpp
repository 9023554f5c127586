#pragma once
// An independent reference for the strength-reduction searches of a simple slope: Bishop's
// simplified method of slices on circular slip surfaces (moment equilibrium about the
// circle's centre), in plane strain and for a slope of finite width W between two rough end
// walls. There the slip surface is the circle extruded over W and closed by the two planar end
// faces at the walls, whose shear strength c' + K sigma_v tan(phi') also resists the rotation
// (the cylinder-with-end-planes construction of Baligh & Azzouz 1975 and Gens, Hutchinson &
// Cavounidis 1988, here with friction on the end planes). The minimum over circles is found by
// a grid of centres and radii refined by a pattern search.
#include <vector>

namespace talus::verify_cases {

struct SlopeSection {
  /// The ground surface y(x) as a polyline in increasing x (constant beyond its ends).
  std::vector<double> surface_x, surface_y;
  double base_y = 0;      ///< firm base: circles reach no lower
  double unit_weight = 0; ///< gamma
  double cohesion = 0;    ///< c'
  double tan_phi = 0;     ///< tan(phi')
};

struct SlipCircle {
  double factor = 0; ///< the factor of safety of this circle
  double centre_x = 0, centre_y = 0, radius = 0;
};

/// Bishop's factor of a circle; `width` <= 0 is plane strain, otherwise the end planes
/// with horizontal stress K sigma_v. Factor 0 when the circle cuts no slip mass.
SlipCircle bishop_circle(const SlopeSection& s, double centre_x, double centre_y, double radius,
                         double width, double end_stress_ratio);

/// The circle of least factor.
SlipCircle critical_circle(const SlopeSection& s, double width, double end_stress_ratio);

} // namespace talus::verify_cases
