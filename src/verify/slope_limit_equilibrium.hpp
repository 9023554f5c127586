#pragma once
// An independent reference for the strength-reduction searches of a simple slope: Bishop's
// simplified method (moment equilibrium about a horizontal axis along z, each column's normal
// force from its vertical equilibrium) in plane strain, and for a slope of finite width W
// between two rough end walls at z = 0 and z = W. There the slip surface is a surface of
// revolution about the axis, truncated by the walls; the planar end faces it leaves on the walls
// resist the rotation with the strength c' + K sigma_v tan(phi'). The surfaces are
//  * the circle extruded over W (the cylinder with end planes of Baligh & Azzouz 1975 and
//    Gens, Hutchinson & Cavounidis 1988, here with friction on the end planes), and
//  * surfaces that curve away from the walls, r(z) = R (1 - |2 (z - W/2) / L|^p)^(1/p), by
//    Hungr's (1987, Geotechnique 37(1)) extension of Bishop's method to columns: a cylinder
//    as p grows, an ellipsoid at p = 2; L > W leaves end planes of radius r(0) on the walls.
// The minimum over each family is found by a grid of trial surfaces refined by a pattern search.
#include "talus/spec/case_spec.hpp"

#include <limits>
#include <vector>

namespace talus::verify_cases {

struct SlopeSection {
  /// The ground surface y(x) as a polyline in increasing x (constant beyond its ends).
  std::vector<double> surface_x, surface_y;
  double base_y = 0;      ///< firm base: slip surfaces reach no lower
  double unit_weight = 0; ///< gamma
  /// Water at rest at this level in the slope and in front of it (none: below everything).
  double water_level = -std::numeric_limits<double>::infinity();
  double water_unit_weight = 0; ///< gamma_w
  double cohesion = 0;          ///< c'
  double tan_phi = 0;           ///< tan(phi')
};

/// Griffiths & Lane's (1999) slope (verification/slope_fos.yaml: the face from the crest
/// (12, 10) to the toe (32, 0) on a firm base at y = 0) with the soil and gravity of `spec`,
/// and its water at rest at the water table's level (a level table) when it has one.
SlopeSection griffiths_lane_section(const CaseSpec& spec);

struct SlipCircle {
  double factor = 0; ///< the factor of safety of this circle
  double centre_x = 0, centre_y = 0, radius = 0;
};

/// Bishop's factor of a circle; `width` <= 0 is plane strain, otherwise the cylinder over the
/// width with end planes under horizontal stress K sigma_v. Factor 0 when the circle cuts no
/// slip mass.
SlipCircle bishop_circle(const SlopeSection& s, double centre_x, double centre_y, double radius,
                         double width, double end_stress_ratio);

/// The circle of least factor.
SlipCircle critical_circle(const SlopeSection& s, double width, double end_stress_ratio);

/// A slip surface of revolution about the horizontal axis through (centre_x, centre_y) along z,
/// symmetric about the mid-width z = W / 2: radius R (1 - |2 (z - W/2) / length|^exponent)^(1 /
/// exponent) at z (the cylinder of radius R when length is infinite).
struct SlipSurface {
  double factor = 0; ///< the factor of safety of this surface
  double centre_x = 0, centre_y = 0, radius = 0;
  double length = std::numeric_limits<double>::infinity();
  double exponent = 2;
};

/// Hungr's 3D Bishop factor of `surface` (its factor ignored) on a slope of `width` > 0 between
/// rough walls; factor 0 when it cuts no slip mass.
SlipSurface bishop_surface(const SlopeSection& s, const SlipSurface& surface, double width,
                           double end_stress_ratio);

/// The surface of least factor over the cylinders and the profiles of each exponent in
/// `exponents` (every length, including those shorter than the width that miss the walls).
SlipSurface critical_surface(const SlopeSection& s, double width, double end_stress_ratio,
                             const std::vector<double>& exponents);

} // namespace talus::verify_cases
