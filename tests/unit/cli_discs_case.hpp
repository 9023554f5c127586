#pragma once
// The colliding-discs case the CLI tests run (test_cli.cpp, test_cli_commands.cpp), and its
// edits.
#include "cli_support.hpp"

#include <algorithm>
#include <string>
#include <vector>

namespace talus::test_support {

// The content of cases/colliding_discs.yaml without its comment lines. The expected
// `case.yaml:<line>:<column>` locations below refer to this text (line 1 is "name: ...").
inline const std::string kCase = R"(name: colliding_discs
analysis: explicit
grid:
  origin: [0, 0]
  extent: [1, 1]
  cell_size: 0.025
materials:
  - name: disc
    model: neo_hookean
    density: 20
    youngs_modulus: 1.0e5
    poisson_ratio: 0.3
bodies:
  - name: lower
    material: disc
    shape: disc
    centre: [0.2, 0.2]
    radius: 0.2
    particles_per_cell: 2
    velocity: [5, 5]
  - name: upper
    material: disc
    shape: disc
    centre: [0.8, 0.8]
    radius: 0.2
    particles_per_cell: 2
    velocity: [-5, -5]
time:
  end_time: 0.07
  cfl: 0.5
output:
  every_time: 0.0025
  fields: [velocity, mass, volume, F, stress, material]
probes:
  - {name: lower_centre, point: [0.2, 0.2]}
  - {name: upper_centre, point: [0.8, 0.8]}
solver:
  shape: gimp
  scheme: musl
  transfer: flip
  flip: 1.0
)";

/// kCase (or `text`) with the one occurrence of `from` replaced by `to`.
inline std::string edited(const std::string& from, const std::string& to,
                          std::string text = kCase) {
  return replaced_once(from, to, std::move(text));
}

inline bool contains(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

} // namespace talus::test_support
