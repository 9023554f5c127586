#pragma once
// Internal to the case reader (src/io/): small helpers of its checks and messages: numbers,
// vectors and the grid's box as the messages print them, key paths, how a YAML node looks, and
// questions about the case read so far (which stage is explicit, what strength can be reduced).
#include "talus/spec/case_spec.hpp"

#include "yaml_support.hpp"

#include <algorithm>
#include <fmt/format.h>
#include <string>
#include <vector>
#include <yaml-cpp/yaml.h>

namespace talus::detail {

/// A computed number for a message: 10 significant digits hide round-off (0.2 - 0.25 prints as
/// -0.05). Values the user typed are quoted from the YAML text instead.
inline std::string num(double v) {
  return fmt::format("{:.10g}", v);
}
/// [x, y] or [x, y, z]: the first `dimension` components.
inline std::string vec(const Vec3& v, int dimension) {
  std::string s = "[" + num(v.x()) + ", " + num(v.y());
  if (dimension == 3)
    s += ", " + num(v.z());
  return s + "]";
}
inline std::string vec(const Vec2& v) {
  return "[" + num(v.x()) + ", " + num(v.y()) + "]";
}

inline bool starts_with(const std::string& s, const std::string& prefix) {
  return s.size() >= prefix.size() && s.compare(0, prefix.size(), prefix) == 0;
}

/// True when `inner` is `outer` or lies below it ("a.b" and "a[0]" lie below "a").
inline bool within(const std::string& inner, const std::string& outer) {
  if (outer.empty())
    return true;
  return inner == outer || starts_with(inner, outer + ".") || starts_with(inner, outer + "[");
}

/// "stage 'name'" of the first explicit stage ("the analysis" without stages), or empty.
inline std::string explicit_stage(const CaseSpec& spec) {
  if (spec.stages.empty())
    return spec.analysis == AnalysisType::Explicit ? "the analysis" : "";
  for (const StageSpec& stage : spec.stages)
    if (stage.analysis == AnalysisType::Explicit)
      return "stage '" + stage.name + "'";
  return "";
}

inline bool any_implicit_stage(const CaseSpec& spec) {
  if (spec.stages.empty())
    return spec.analysis != AnalysisType::Explicit;
  return std::any_of(spec.stages.begin(), spec.stages.end(), [](const StageSpec& stage) {
    return stage.analysis != AnalysisType::Explicit;
  });
}

/// Whether a strength factor has anything to divide (c and tan(phi) of a frictional model).
inline bool has_reducible_material(const std::vector<MaterialSpec>& materials) {
  return std::any_of(materials.begin(), materials.end(), [](const MaterialSpec& mat) {
    return mat.model == MaterialModel::Tresca || mat.model == MaterialModel::MohrCoulomb ||
           mat.model == MaterialModel::DruckerPrager;
  });
}

/// How a node looks, for "expected X, got Y" messages.
inline std::string describe(const YAML::Node& n) {
  switch (n.Type()) {
  case YAML::NodeType::Null:
    return "an empty value";
  case YAML::NodeType::Scalar:
    if (n.Tag() == "!")
      return "the quoted string \"" + shown(n.Scalar()) + "\"";
    return "'" + shown(n.Scalar()) + "'";
  case YAML::NodeType::Sequence:
    return "a list";
  case YAML::NodeType::Map:
    return "a map";
  case YAML::NodeType::Undefined:
    break;
  }
  return "nothing";
}

/// Whether a[d] < b[d] along every one of the first `dimension` axes.
inline bool below_along_all(const Vec3& a, const Vec3& b, int dimension) {
  for (int d = 0; d < dimension; ++d)
    if (!(a[d] < b[d]))
      return false;
  return true;
}

/// Whether p lies in the grid's box (with a round-off margin), and the box for a message.
inline bool inside_grid(const Vec3& p, const GridSpec& g) {
  const Vec3 lo = g.origin, hi = g.origin + g.extent;
  const double tol = 1e-12 * (g.origin.cwiseAbs().maxCoeff() + g.extent.maxCoeff());
  for (int d = 0; d < g.dimension; ++d)
    if (!(p[d] >= lo[d] - tol && p[d] <= hi[d] + tol))
      return false;
  return true;
}
inline std::string grid_box(const GridSpec& g) {
  const Vec3 lo = g.origin, hi = g.origin + g.extent;
  std::string s = fmt::format("the grid covers x in [{}, {}], y in [{}, {}]", num(lo.x()),
                              num(hi.x()), num(lo.y()), num(hi.y()));
  if (g.dimension == 3)
    s += fmt::format(", z in [{}, {}]", num(lo.z()), num(hi.z()));
  return s;
}

} // namespace talus::detail
