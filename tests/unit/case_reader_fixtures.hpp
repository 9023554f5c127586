#pragma once
// The case texts and helpers the case-reader tests share (test_case_reader.cpp: valid input
// and --set overrides; test_case_reader_errors.cpp: every error class at its location).
#include "talus/io/case_reader.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace talus::case_reader_test {

// Line numbers below refer to this text (line 1 is "name: colliding_discs").
inline const std::string kCase = R"(name: colliding_discs
analysis: explicit
dimension: 2
grid:
  origin: [-0.5, 0]
  extent: [1.5, 1]
  cell_size: 0.025
materials:
  - name: disc
    model: linear_elastic
    density: 20
    youngs_modulus: 1.0e5
    poisson_ratio: 0.3
  - name: rubber
    model: neo_hookean
    density: 1100
    youngs_modulus: 2e6
    poisson_ratio: 0.45
bodies:
  - name: lower
    material: disc
    shape: disc
    centre: [0.2, 0.2]
    radius: 0.2
    velocity: [7, -7]
  - name: upper
    material: rubber
    shape: rectangle
    min: [0.5, 0.5]
    max: [0.8, 0.9]
    particles_per_cell: 3
    angular_velocity: -1.5
  - name: wedge
    material: disc
    shape: polygon
    vertices: [[-0.4, 0.1], [-0.1, 0.1], [-0.25, 0.4]]
gravity: [0, -9.81]
boundaries:
  x_min: fixed
  y_min: roller
point_loads:
  - {name: tip, point: [0.8, 0.9], force: [0, -10]}
  - {point: [0.2, 0.2], force: [1, 0]}
tractions:
  - {body: upper, side: top, traction: [0, -100]}
time:
  end_time: 0.05
  cfl: 0.5
  max_steps: 100000
output:
  every_steps: 10
  fields: [velocity, F, stress]
probes:
  - {name: tip, point: [0.8, 0.9]}
  - {name: first, particle: 0}
solver:
  shape: linear
  scheme: usf
  flip: 0.95
)";

// The smallest valid case: everything optional left out. Its step is below the explicit
// stability limit h / c_p = 8.5e-5 s, which the reader enforces.
inline const std::string kMinimal = R"(name: minimal
grid:
  extent: [2, 1]
  cell_size: 0.5
materials:
  - {name: steel, model: linear_elastic, density: 7800, youngs_modulus: 2e11, poisson_ratio: 0.3}
bodies:
  - {name: block, material: steel, shape: rectangle, min: [0.5, 0], max: [1.5, 0.5]}
time:
  end_time: 1
  dt: 5e-5
)";

/// `text` with the first occurrence of `from` replaced by `to` (which must exist).
inline std::string with(const std::string& text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << "test bug: '" << from << "' not in the case text";
  if (at == std::string::npos)
    return text;
  std::string out = text;
  out.replace(at, from.size(), to);
  return out;
}

struct Expected {
  std::string file = "case.yaml";
  int line;
  int column;
  std::string key_path;
  std::string message_part;
};

/// Reads `text` expecting an InputError at exactly `e`.
inline void expect_error(const std::string& text, const Expected& e,
                         const std::vector<std::string>& overrides = {}) {
  try {
    read_case_text(text, "case.yaml", overrides);
    ADD_FAILURE() << "expected InputError containing '" << e.message_part << "'";
  } catch (const InputError& err) {
    EXPECT_EQ(err.where().file, e.file) << err.what();
    EXPECT_EQ(err.where().line, e.line) << err.what();
    EXPECT_EQ(err.where().column, e.column) << err.what();
    EXPECT_EQ(err.where().key_path, e.key_path) << err.what();
    EXPECT_NE(std::string(err.what()).find(e.message_part), std::string::npos)
        << "message: " << err.what() << "\nexpected to contain: " << e.message_part;
  }
}

inline void expect_vec(const Vec2& v, double x, double y) {
  EXPECT_DOUBLE_EQ(v.x(), x);
  EXPECT_DOUBLE_EQ(v.y(), y);
}
/// A 2D case's point: x, y and z = 0.
inline void expect_vec(const Vec3& v, double x, double y) {
  EXPECT_DOUBLE_EQ(v.x(), x);
  EXPECT_DOUBLE_EQ(v.y(), y);
  EXPECT_EQ(v.z(), 0.0);
}

} // namespace talus::case_reader_test
