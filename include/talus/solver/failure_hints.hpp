#pragma once
// The likely causes of a numerical failure, read from the case itself, for the message a failed
// run ends with: a unit mistake (the plausibility warnings), a body nothing holds in a
// quasi-static analysis, a time step too large for the motion, or a load past the soil's limit.
#include "talus/scene/scene.hpp"
#include "talus/spec/case_spec.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <string>
#include <vector>

namespace talus {

/// The analysis the run failed in, and whether Newton stalled at the smallest load step.
struct FailureContext {
  AnalysisType analysis = AnalysisType::Explicit;
  bool newton_stalled = false;
};

/// One sentence per likely cause, most likely first; empty when the case suggests none.
std::vector<std::string> likely_failure_causes(const CaseSpec& spec, const FailureContext& context);

/// "Likely causes: (1) ...; (2) ..." or empty.
std::string describe_likely_causes(const std::vector<std::string>& causes);

/// " (the point at [x, y], initially [x0, y0], in body 'b')": where point p of the scene is,
/// for a failure that names it; empty when p is not one of the scene's points.
template <int Dim> std::string where_point_is(const Scene<Dim>& scene, long long p) {
  const auto& P = scene.particles;
  if (p < 0 || p >= static_cast<long long>(P.size()))
    return {};
  const auto s = static_cast<std::size_t>(p);
  const auto body = static_cast<std::size_t>(P.body[s]);
  return fmt::format(" (the point at [{:.4g}], initially [{:.4g}], in body '{}')",
                     fmt::join(P.x[s], ", "), fmt::join(P.x0[s], ", "),
                     body < scene.spec.bodies.size() ? scene.spec.bodies[body].name : "?");
}

} // namespace talus
