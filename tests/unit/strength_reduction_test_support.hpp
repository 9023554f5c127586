#pragma once
// The cases and helpers the strength-reduction tests share (test_strength_reduction.cpp: the
// section, the weakened materials, the bisection, the trial classification;
// test_stop_after_step.cpp: the run hook that ends a trial and small searches end to end).
#include "talus/core/errors.hpp"
#include "talus/io/case_reader.hpp"
#include "talus/io/csv.hpp"
#include "talus/io/results.hpp"
#include "talus/scene/scene.hpp"
#include "talus/solver/fos_refinement.hpp"
#include "talus/solver/run.hpp"
#include "talus/solver/strength_reduction.hpp"
#include "temporary_directory.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

namespace talus::strength_reduction_test {

namespace fs = std::filesystem;

// A coarse 2:1 slope (Griffiths & Lane's shape, 2 m cells): cheap enough for a unit test.
inline const std::string kSlope = R"(name: small_slope
analysis: implicit_quasistatic
grid: {origin: [0, 0], extent: [40, 12], cell_size: 2}
materials:
  - {name: soil, model: mohr_coulomb, density: 2000, youngs_modulus: 1.0e8, poisson_ratio: 0.3,
     cohesion: 1.0e4, friction_angle: 20, dilation_angle: 5,
     residual: {cohesion: 5.0e3, friction_angle: 15, plastic_strain: 0.1}}
  - {name: rock, model: linear_elastic, density: 2500, youngs_modulus: 1.0e9, poisson_ratio: 0.2}
bodies:
  - {name: slope, material: soil, shape: polygon, vertices: [[0, 0], [32, 0], [12, 10], [0, 10]]}
gravity: [0, -10]
boundaries: {x_min: roller, y_min: fixed}
time: {end_time: 1, dt: 0.5, min_dt: 0.125, max_steps: 50}
output: {every_steps: 1}
probes:
  - {name: crest, point: [12, 10]}
strength_reduction: {lower: 1.0, upper: 4.0, tolerance: 0.5, probe: crest}
)";

/// `text` with the first occurrence of `from` replaced by `to` (which must exist).
inline std::string with(const std::string& text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << "test bug: '" << from << "' not in the case text";
  std::string out = text;
  if (at != std::string::npos)
    out.replace(at, from.size(), to);
  return out;
}

// An elastic block on the grid's base under its own weight: a few cheap steps.
inline const std::string kBlock = R"(name: block
analysis: implicit_quasistatic
grid: {origin: [0, 0], extent: [1, 3], cell_size: 0.25}
materials:
  - {name: soil, model: linear_elastic, density: 2000, youngs_modulus: 1.0e7, poisson_ratio: 0.3}
bodies:
  - {name: block, material: soil, shape: rectangle, min: [0, 0], max: [1, 2]}
gravity: [0, -9.81]
boundaries: {y_min: fixed}
time: {end_time: 1, dt: 0.25}
output: {every_steps: 1}
)";

inline nlohmann::json read_json(const fs::path& file) {
  return nlohmann::json::parse(std::ifstream(file));
}

} // namespace talus::strength_reduction_test
