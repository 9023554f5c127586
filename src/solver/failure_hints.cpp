// Likely causes of a numerical failure (talus/solver/failure_hints.hpp).
#include "talus/solver/failure_hints.hpp"

#include "talus/io/plausibility.hpp"
#include "talus/scene/body_geometry.hpp"

#include <algorithm>
#include <fmt/format.h>
#include <fmt/ranges.h>

namespace talus {
namespace {

/// Whether the body (its bounding box) reaches within a cell of a fixed or roller grid face, or
/// of a prescribed box: something that holds it against rigid motion.
bool body_is_held(const CaseSpec& spec, const BodySpec& body) {
  Vec3 lo, hi;
  bounding_box(body, spec.dimension, lo, hi);
  const double h = spec.grid.cell_size;
  for (int f = 0; f < face_count(spec.dimension); ++f) {
    if (spec.boundaries[f] == FaceCondition::Free || spec.boundaries[f] == FaceCondition::Platen)
      continue;
    const int a = face_axis(f);
    const double face = spec.grid.origin[a] + (face_is_upper(f) ? spec.grid.extent[a] : 0.0);
    if (face_is_upper(f) ? hi[a] >= face - h : lo[a] <= face + h)
      return true;
  }
  return std::any_of(spec.prescribed.begin(), spec.prescribed.end(), [&](const auto& box) {
    for (int d = 0; d < spec.dimension; ++d)
      if (box.max[d] < lo[d] - h || box.min[d] > hi[d] + h)
        return false;
    return true;
  });
}

bool any_plastic(const CaseSpec& spec) {
  return std::any_of(spec.materials.begin(), spec.materials.end(),
                     [](const MaterialSpec& m) { return is_plastic(m.model); });
}

} // namespace

std::vector<std::string> likely_failure_causes(const CaseSpec& spec,
                                               const FailureContext& context) {
  std::vector<std::string> causes;
  const std::vector<PlausibilityWarning> warnings = plausibility_warnings(spec);
  if (!warnings.empty()) {
    std::vector<std::string> keys;
    for (const PlausibilityWarning& w : warnings)
      keys.push_back(w.where.key_path);
    causes.push_back(fmt::format("a unit mistake: {} {} far from any soil or rock (the warnings "
                                 "printed at the start say why)",
                                 fmt::join(keys, ", "), keys.size() == 1 ? "is" : "are"));
  }
  if (context.analysis == AnalysisType::ImplicitQuasistatic)
    for (const BodySpec& body : spec.bodies)
      if (!body_is_held(spec, body))
        causes.push_back(fmt::format(
            "body '{}' touches no fixed or roller face and no prescribed box: nothing holds it "
            "against rigid motion, so the quasi-static tangent is singular (fix a face, or use "
            "implicit_dynamic)",
            body.name));
  switch (context.analysis) {
  case AnalysisType::Explicit:
    causes.push_back(fmt::format("a time step too large for the motion: points that cross "
                                 "more than a cell per step invert their cells; lower {}",
                                 spec.time.cfl ? fmt::format("time.cfl (now {:g})", *spec.time.cfl)
                                               : std::string("time.dt")));
    break;
  case AnalysisType::ImplicitDynamic:
    causes.push_back("a time step too large for the motion: lower time.dt (or time.min_dt to let "
                     "the stepper cut back further)");
    break;
  case AnalysisType::ImplicitQuasistatic:
    if (context.newton_stalled && any_plastic(spec))
      causes.push_back("the load has reached the soil's limit: a footing past its bearing "
                       "capacity or a slope past failure stalls Newton at the limit load, which "
                       "is then the answer (the last converged step is written; see "
                       "timeseries.csv)");
    break;
  }
  return causes;
}

std::string describe_likely_causes(const std::vector<std::string>& causes) {
  if (causes.empty())
    return {};
  std::string out = "Likely causes:";
  for (std::size_t i = 0; i < causes.size(); ++i)
    out += fmt::format(" ({}) {}{}", i + 1, causes[i], i + 1 < causes.size() ? ";" : ".");
  return out;
}

} // namespace talus
