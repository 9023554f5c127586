// Plausibility warnings (talus/io/plausibility.hpp). The bounds are wide on purpose: a warning
// must point at a likely mistake, not at an unusual soil. Each bound's reason is next to it.
#include "talus/io/plausibility.hpp"

#include "talus/io/case_vocabulary.hpp"
#include "talus/material/material.hpp"
#include "talus/scene/body_geometry.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <numbers>

namespace talus {
namespace {

// Soils weigh 1300-2300 kg/m^3, rocks 2000-3000, steel 7850: a density outside [500, 10000] is
// most often a unit weight in N/m^3 (18 kN/m^3 typed as 18000) or in kN/m^3, or tonnes per m^3.
constexpr double kMinDensity = 500, kMaxDensity = 10000;
// Peat and very soft clay have E of about 0.5-1 MPa, steel 210 GPa, diamond 1.2 TPa.
constexpr double kMinModulus = 1e5, kMaxModulus = 1.2e12;
// A body that its own weight would shorten by half is not a soil or a rock in Pa.
constexpr double kMaxSelfWeightStrain = 0.5;
// A soil's cohesion is rarely below a thousandth of the vertical stress at the base of a slope
// or column (c = 1 kPa is small even for a 10 m slope, where rho g H is about 200 kPa); far
// below it, a strength typed in kPa (c = 10 for 10 kPa) is the likely cause.
constexpr double kMinStrengthOverWeight = 1e-3;
// Undrained clays have E of 300 to 1500 c_u; steel's yield stress is 1e-3 E. A strength above a
// tenth of E mixes units (E in MPa, c in Pa).
constexpr double kMaxStrengthOverModulus = 0.1;
// Intact rock has a cohesion of tens of MPa at most.
constexpr double kMaxStrength = 1e9;
// Friction angles of soils and rock joints lie between about 15 and 55 degrees.
constexpr double kMaxFrictionAngle = 60;
// Earth's 9.81 m/s^2; a geotechnical centrifuge reaches a few hundred g.
constexpr double kMinGravity = 0.5, kMaxGravity = 5000;
// Hydraulic conductivities: intact clay 1e-12 m/s, clean gravel 1e-2; an intrinsic
// permeability in m^2 (about 1e-7 of k in m/s for water) falls far below.
constexpr double kMinPermeability = 1e-13, kMaxPermeability = 1;
// Equal-order u and p overshoot next to a drained face when a load or the water table changes
// in steps shorter than about h^2 / (6 c_v) (Vermeer & Verruijt 1981's bound for linear
// elements; docs/verification.md, terzaghi, measures the overshoot).
constexpr double kConsolidationStepFactor = 1.0 / 6.0;

/// 196 kPa, 20 MPa, 12 Pa: a stress with its SI prefix, as an engineer reads it.
std::string pressure(double pa) {
  const double a = std::abs(pa);
  if (a >= 1e9)
    return fmt::format("{:.3g} GPa", pa / 1e9);
  if (a >= 1e6)
    return fmt::format("{:.3g} MPa", pa / 1e6);
  if (a >= 1e3)
    return fmt::format("{:.3g} kPa", pa / 1e3);
  return fmt::format("{:.3g} Pa", pa);
}

/// The warnings of one case, collected with the location of each value.
class Collector {
public:
  explicit Collector(const CaseSpec& spec) : spec_(spec) {}

  /// `key` is the value's key path; the location falls back to `fallback` (a value the reader
  /// did not find in a map, or a default).
  void add(PlausibilityCheck check, const std::string& key, const SourceLocation& fallback,
           std::string message) {
    if (std::find(spec_.silenced_warnings.begin(), spec_.silenced_warnings.end(), check) !=
        spec_.silenced_warnings.end())
      return;
    warnings_.push_back({check, spec_.location_of(key, fallback), std::move(message)});
  }
  std::vector<PlausibilityWarning> take() { return std::move(warnings_); }

private:
  const CaseSpec& spec_;
  std::vector<PlausibilityWarning> warnings_;
};

/// The tallest body of material `m` along gravity (its height H for rho g H), or none.
const BodySpec* tallest_body(const CaseSpec& spec, int m, double& height) {
  const Vec3 down = spec.gravity.normalized();
  const BodySpec* tallest = nullptr;
  height = 0;
  for (const BodySpec& b : spec.bodies) {
    if (b.material_index != m)
      continue;
    Vec3 lo, hi;
    bounding_box(b, spec.dimension, lo, hi);
    const double h = down.cwiseAbs().dot(hi - lo);
    if (tallest == nullptr || h > height) {
      tallest = &b;
      height = h;
    }
  }
  return tallest;
}

void check_density(Collector& out, const MaterialSpec& s, const std::string& key, double g,
                   bool by_weight) {
  if (s.density >= kMinDensity && s.density <= kMaxDensity)
    return;
  const bool low = s.density < kMinDensity;
  if (by_weight) {
    const double gamma = s.density * g;
    out.add(PlausibilityCheck::Density, key, s.where,
            fmt::format("material '{}' has a unit weight of {:g} N/m^3, far {} soils and rocks "
                        "(13-30 kN/m^3){}",
                        s.name, gamma, low ? "below" : "above",
                        low ? fmt::format(": kN/m^3? Talus takes N/m^3, so {:g} kN/m^3 is {:g}",
                                          gamma, gamma * 1e3)
                            : std::string()));
    return;
  }
  // The likely slip depends on the number: 1.8 is t/m^3, 18 a unit weight in kN/m^3, 18000 one
  // in N/m^3.
  std::string hint = "soils weigh 1300-2300 kg/m^3";
  if (s.density >= 1 && s.density <= 4)
    hint =
        fmt::format("t/m^3? Talus takes kg/m^3, so {:g} t/m^3 is {:g}", s.density, s.density * 1e3);
  else if (s.density >= 10 && s.density <= 30)
    hint = fmt::format("a unit weight in kN/m^3? Talus takes kg/m^3, or write unit_weight: {:g} "
                       "(N/m^3)",
                       s.density * 1e3);
  else if (!low && g > 0)
    hint = fmt::format("a unit weight typed as a density? {:g} N/m^3 is {:.4g} kg/m^3 (write "
                       "unit_weight: {:g})",
                       s.density, s.density / g, s.density);
  out.add(PlausibilityCheck::Density, key, s.where,
          fmt::format("material '{}' has a density of {:g} kg/m^3, far {} soils and rocks "
                      "(1300-3000 kg/m^3): {}",
                      s.name, s.density, low ? "below" : "above", hint));
}

void check_modulus(Collector& out, const CaseSpec& spec, int m, const std::string& prefix) {
  const MaterialSpec& s = spec.materials[static_cast<std::size_t>(m)];
  const std::string key = prefix + ".youngs_modulus";
  const double E = s.youngs_modulus;
  if (E < kMinModulus) {
    // The conversions that give a plausible modulus: E typed in MPa or in kPa.
    std::string hint = "Talus takes pascals";
    if (E * 1e6 >= kMinModulus)
      hint += fmt::format(", so {:g} MPa is {:g}", E, E * 1e6);
    if (E * 1e3 >= kMinModulus)
      hint += fmt::format(" and {:g} kPa is {:g}", E, E * 1e3);
    out.add(PlausibilityCheck::YoungsModulus, key, s.where,
            fmt::format("material '{}' has Young's modulus {}, far below the softest soils (about "
                        "1 MPa for soft clay): {}",
                        s.name, pressure(E), hint));
    return;
  }
  if (E > kMaxModulus) {
    out.add(PlausibilityCheck::YoungsModulus, key, s.where,
            fmt::format("material '{}' has Young's modulus {}, above any soil, rock or metal",
                        s.name, pressure(E)));
    return;
  }
  const double g = spec.gravity.norm();
  double height = 0;
  const BodySpec* body = g > 0 ? tallest_body(spec, m, height) : nullptr;
  const double weight = s.density * g * height;
  if (body != nullptr && weight > kMaxSelfWeightStrain * E)
    out.add(PlausibilityCheck::YoungsModulus, key, s.where,
            fmt::format("material '{}' has Young's modulus {}, but the weight at the base of body "
                        "'{}' is rho g H = {} ({:.2g} E): the body would sink under its own "
                        "weight; is E in Pa?",
                        s.name, pressure(E), body->name, pressure(weight), weight / E));
}

/// Cohesion (tresca, mohr_coulomb, drucker_prager) or yield stress (von_mises).
void check_strength(Collector& out, const CaseSpec& spec, int m, const std::string& prefix) {
  const MaterialSpec& s = spec.materials[static_cast<std::size_t>(m)];
  const bool mises = s.model == MaterialModel::VonMises;
  const double c = mises ? s.yield_stress : s.cohesion;
  const std::string name = mises ? "yield stress" : "cohesion";
  const std::string key = prefix + (mises ? ".yield_stress" : ".cohesion");
  if (c <= 0)
    return;
  if (c > kMaxStrength) {
    out.add(PlausibilityCheck::Strength, key, s.where,
            fmt::format("material '{}' has a {} of {}, above intact rock's", s.name, name,
                        pressure(c)));
    return;
  }
  if (c > kMaxStrengthOverModulus * s.youngs_modulus) {
    out.add(PlausibilityCheck::Strength, key, s.where,
            fmt::format("material '{}' has a {} of {}, {:.2g} of its Young's modulus {} (soils: "
                        "1e-3 to 1e-2): are both in Pa?",
                        s.name, name, pressure(c), c / s.youngs_modulus,
                        pressure(s.youngs_modulus)));
    return;
  }
  const double g = spec.gravity.norm();
  double height = 0;
  const BodySpec* body = g > 0 ? tallest_body(spec, m, height) : nullptr;
  const double weight = s.density * g * height;
  if (body != nullptr && c < kMinStrengthOverWeight * weight)
    out.add(PlausibilityCheck::Strength, key, s.where,
            fmt::format("material '{}' has a {} of {}, {:.2g} of the vertical stress at the base "
                        "of body '{}' (rho g H = {}): typed in kPa? Talus takes pascals, so "
                        "{:g} kPa is {:g}",
                        s.name, name, pressure(c), c / weight, body->name, pressure(weight), c,
                        c * 1e3));
}

void check_friction_angle(Collector& out, const MaterialSpec& s, const std::string& prefix) {
  if (s.model != MaterialModel::MohrCoulomb && s.model != MaterialModel::DruckerPrager)
    return;
  const double phi = s.friction_angle;
  const std::string key = prefix + ".friction_angle";
  if (phi > 0 && phi < 1)
    out.add(PlausibilityCheck::FrictionAngle, key, s.where,
            fmt::format("material '{}' has a friction angle of {:g} degrees: radians? Talus takes "
                        "degrees ({:g} rad is {:.3g} degrees)",
                        s.name, phi, phi, phi * 180 / std::numbers::pi));
  else if (phi > kMaxFrictionAngle)
    out.add(PlausibilityCheck::FrictionAngle, key, s.where,
            fmt::format("material '{}' has a friction angle of {:g} degrees, above any soil or "
                        "rock joint (15-55 degrees)",
                        s.name, phi));
}

void check_loads(Collector& out, const CaseSpec& spec) {
  for (std::size_t i = 0; i < spec.tractions.size(); ++i) {
    const TractionSpec& t = spec.tractions[i];
    const BodySpec& body = spec.bodies[static_cast<std::size_t>(t.body_index)];
    const MaterialSpec& s = spec.materials[static_cast<std::size_t>(body.material_index)];
    const double q = t.traction.norm();
    if (q > s.youngs_modulus)
      out.add(PlausibilityCheck::Load, fmt::format("tractions[{}].traction", i), t.where,
              fmt::format("the traction on body '{}' is {}, above the Young's modulus of its "
                          "material '{}' ({}): strains of order one from the load alone; is "
                          "the traction in Pa?",
                          body.name, pressure(q), s.name, pressure(s.youngs_modulus)));
  }
}

/// A point load acts on one point; spread over a cell face (a cell's width per metre in plane
/// strain, per radian at its radius in axisymmetry, a cell's face in 3D) it should not exceed
/// the modulus of the body it loads.
void check_point_loads(Collector& out, const CaseSpec& spec) {
  const double h = spec.grid.cell_size;
  for (std::size_t i = 0; i < spec.point_loads.size(); ++i) {
    const PointLoadSpec& load = spec.point_loads[i];
    const double area = spec.dimension == 3                       ? h * h
                        : spec.geometry == Geometry::Axisymmetric ? h * std::max(load.point[0], h)
                                                                  : h;
    const double q = load.force.norm() / area;
    for (const BodySpec& body : spec.bodies) {
      Vec3 lo, hi;
      bounding_box(body, spec.dimension, lo, hi);
      bool inside = true;
      for (int d = 0; d < spec.dimension; ++d)
        inside = inside && load.point[d] >= lo[d] - h && load.point[d] <= hi[d] + h;
      if (!inside)
        continue;
      const MaterialSpec& s = spec.materials[static_cast<std::size_t>(body.material_index)];
      if (q > s.youngs_modulus)
        out.add(PlausibilityCheck::Load, fmt::format("point_loads[{}].force", i), load.where,
                fmt::format("point load '{}' spread over a cell face ({:g} m) is {}, above the "
                            "Young's modulus of body '{}' ({}): strains of order one under the "
                            "point; is the force in N (per metre in plane strain, per radian in "
                            "axisymmetry)?",
                            load.name, h, pressure(q), body.name, pressure(s.youngs_modulus)));
      break;
    }
  }
}

void check_gravity(Collector& out, const CaseSpec& spec) {
  const double g = spec.gravity.norm();
  if (g == 0 || (g >= kMinGravity && g <= kMaxGravity))
    return;
  out.add(PlausibilityCheck::Gravity, "gravity", SourceLocation{spec.source_file, 0, 0, "gravity"},
          fmt::format("gravity is {:g} m/s^2; Earth's is 9.81 (a centrifuge model at N g has "
                      "N x 9.81)",
                      g));
}

void check_displacements(Collector& out, const CaseSpec& spec) {
  for (std::size_t i = 0; i < spec.prescribed.size(); ++i) {
    const PrescribedSpec& p = spec.prescribed[i];
    for (int d = 0; d < spec.dimension; ++d) {
      const auto u = p.displacement[static_cast<std::size_t>(d)];
      if (u && std::abs(*u) > spec.grid.extent[d]) {
        out.add(PlausibilityCheck::Displacement, fmt::format("prescribed[{}].displacement", i),
                p.where,
                fmt::format("prescribed box '{}' moves by {:g} m along {}, more than the grid's "
                            "{:g} m: the displacement is in metres ({:g} mm is {:g} m)",
                            p.name, *u, "xyz"[d], spec.grid.extent[d], *u, *u / 1e3));
        break;
      }
    }
  }
}

void check_permeability(Collector& out, const MaterialSpec& s, const std::string& prefix) {
  if (!s.flow)
    return;
  const double k = s.flow->permeability;
  if (k >= kMinPermeability && k <= kMaxPermeability)
    return;
  out.add(PlausibilityCheck::Permeability, prefix + ".permeability", s.where,
          fmt::format("material '{}' has permeability {:g} m/s, outside [{:g}, {:g}]: Talus takes "
                      "the hydraulic conductivity k in m/s (clay 1e-9 to 1e-7, sand 1e-5 to "
                      "1e-3), not an intrinsic permeability in m^2",
                      s.name, k, kMinPermeability, kMaxPermeability));
}

/// The largest c_v = k / (gamma_w (alpha^2 / M_c + 1 / M)) of the case's materials, and its
/// material.
double largest_consolidation_coefficient(const CaseSpec& spec, const MaterialSpec*& fastest) {
  double largest = 0;
  for (const MaterialSpec& m : spec.materials) {
    const double alpha = m.flow->biot_coefficient;
    const double constrained =
        LameParameters::from_young_poisson(m.youngs_modulus, m.poisson_ratio).p_wave_modulus();
    const double c_v =
        m.flow->permeability /
        (spec.water->unit_weight * (alpha * alpha / constrained + m.flow->inverse_biot_modulus));
    if (c_v > largest) {
      largest = c_v;
      fastest = &m;
    }
  }
  return largest;
}

// A stage that changes the load (the first) or the water table in steps below h^2 / (6 c_v).
void check_consolidation_steps(Collector& out, const CaseSpec& spec) {
  if (!spec.consolidates())
    return;
  const MaterialSpec* fastest = nullptr;
  const double c_v = largest_consolidation_coefficient(spec, fastest);
  if (fastest == nullptr) // no c_v > 0: a modulus so small that 1 / M_c overflowed
    return;
  const double h = spec.grid.cell_size;
  const double limit = kConsolidationStepFactor * h * h / c_v;
  const auto check = [&](const std::string& what, const TimeSpec& time, const std::string& key,
                         const SourceLocation& where) {
    if (!time.dt || *time.dt >= limit)
      return;
    out.add(PlausibilityCheck::ConsolidationStep, key, where,
            fmt::format("{} in steps of {:g} s, shorter than h^2 / (6 c_v) = {:g} s (c_v = {:.3g} "
                        "m^2/s of material '{}', h = {:g} m): the pore pressure overshoots next "
                        "to drained faces after the change and settles within a few cells and "
                        "steps; meant for an undrained load step, otherwise use longer steps",
                        what, *time.dt, limit, c_v, fastest->name, h));
  };
  if (spec.stages.empty()) {
    check("the loads change", spec.time, "time.dt",
          SourceLocation{spec.source_file, 0, 0, "time.dt"});
    return;
  }
  for (std::size_t k = 0; k < spec.stages.size(); ++k) {
    const StageSpec& stage = spec.stages[k];
    if (k == 0 || stage.water)
      check(fmt::format("stage '{}' changes the {}", stage.name, k == 0 ? "loads" : "water table"),
            stage.time, fmt::format("stages[{}].time.dt", k), stage.where);
  }
}

} // namespace

std::vector<PlausibilityWarning> plausibility_warnings(const CaseSpec& spec) {
  Collector out(spec);
  const double g = spec.gravity.norm();
  for (std::size_t m = 0; m < spec.materials.size(); ++m) {
    const MaterialSpec& s = spec.materials[m];
    const std::string prefix = fmt::format("materials[{}]", m);
    const bool by_weight = spec.locations.contains(prefix + ".unit_weight");
    check_density(out, s, prefix + (by_weight ? ".unit_weight" : ".density"), g, by_weight);
    if (s.saturated_density) {
      MaterialSpec wet = s;
      wet.density = *s.saturated_density;
      const bool wet_by_weight = spec.locations.contains(prefix + ".saturated_unit_weight");
      check_density(out, wet,
                    prefix + (wet_by_weight ? ".saturated_unit_weight" : ".saturated_density"), g,
                    wet_by_weight);
    }
    check_modulus(out, spec, static_cast<int>(m), prefix);
    if (is_plastic(s.model))
      check_strength(out, spec, static_cast<int>(m), prefix);
    check_friction_angle(out, s, prefix);
    check_permeability(out, s, prefix);
  }
  check_loads(out, spec);
  check_point_loads(out, spec);
  check_gravity(out, spec);
  check_displacements(out, spec);
  check_consolidation_steps(out, spec);
  return out.take();
}

std::string describe(const PlausibilityWarning& warning) {
  return fmt::format("talus: warning: {}: {} (if this is meant, add silence_warnings: [{}] to the "
                     "case)",
                     warning.where.to_string(), warning.message,
                     choice_word(plausibility_check_choices(), warning.check));
}

} // namespace talus
