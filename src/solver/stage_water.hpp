#pragma once
// The water during a stage (scene.water): a quasi-static stage moves the pore pressure from the
// water table before it to its own with its progress; a dynamic or explicit stage has its own
// from the first step. The first stage of a case whose weight grows from zero (quasi-static,
// no geostatic stress) grows its water with the weight, from none.
#include "talus/scene/scene.hpp"

#include <cstddef>
#include <optional>
#include <vector>

namespace talus {

template <int Dim> class StageWater {
public:
  /// The water of stage k of `stages` (the run's stages of the case `spec`).
  StageWater(Scene<Dim>& scene, const CaseSpec& spec, const std::vector<StageSpec>& stages,
             std::size_t k)
      : scene_(scene), quasi_static_(stages[k].analysis == AnalysisType::ImplicitQuasistatic) {
    const bool weight_grows = k == 0 && quasi_static_ && !spec.starts_geostatic();
    std::optional<WaterTable> from;
    if (!weight_grows)
      from = table_after(spec, stages, static_cast<long>(k) - 1);
    scene_.water = PoreWater(from, table_after(spec, stages, static_cast<long>(k)));
    scene_.water.set_undrained(stages[k].undrained);
  }

  /// Sets the water for a step from the fraction `start` of the stage to `progress`.
  void at(double progress, double start) {
    if (quasi_static_)
      scene_.water.set_progress(progress, start);
    else
      scene_.water.set_progress(1.0);
  }
  void at(double progress) { at(progress, progress); }

private:
  /// The water table at the end of stage k (the case's before the first).
  static std::optional<WaterTable> table_after(const CaseSpec& spec,
                                               const std::vector<StageSpec>& stages, long k) {
    for (; k >= 0; --k)
      if (const auto& w = stages[static_cast<std::size_t>(k)].water)
        return WaterTable(*w);
    return WaterTable::of(spec);
  }

  Scene<Dim>& scene_;
  bool quasi_static_;
};

} // namespace talus
