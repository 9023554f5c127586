#pragma once
// The cases, the fixture and the helpers of the implicit solver's whole-case tests
// (test_implicit.cpp; F-bar: test_implicit_f_bar.cpp). Every run goes to a fresh temporary
// directory that is removed afterwards.
#include "talus/core/errors.hpp"
#include "talus/io/case_reader.hpp"
#include "talus/io/csv.hpp"
#include "talus/io/results.hpp"
#include "talus/linalg/linear_solver.hpp"
#include "talus/scene/scene.hpp"
#include "talus/solver/run.hpp"
#include "temporary_directory.hpp"

#include <Eigen/Core>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace talus::implicit_test {

namespace fs = std::filesystem;
using talus::Index;
using talus::ResultsReader;

// cases/cantilever.yaml without its comments. The beam (L = 8, D = 1, E = 3e5, nu = 0) is
// clamped at the grid's x_min face and loaded by a downward tip shear traction of resultant 1 N.
inline const std::string kCantilever = R"(name: cantilever
analysis: implicit_quasistatic
grid:
  origin: [0, -1.5]
  extent: [10, 3]
  cell_size: 0.125
materials:
  - {name: beam, model: linear_elastic, density: 1000, youngs_modulus: 3.0e5, poisson_ratio: 0}
bodies:
  - {name: beam, material: beam, shape: rectangle, min: [0, -0.5], max: [8, 0.5],
     particles_per_cell: 2}
boundaries: {x_min: fixed}
tractions:
  - {body: beam, side: right, traction: [0, -1.0]}
time: {end_time: 1, dt: 1}
output: {every_steps: 1}
probes:
  - {name: tip, point: [8, 0]}
solver: {shape: gimp, linear_solver: cholmod}
)";

// An elastic block of width 1 and height 2 standing on the grid's y_min face (y = 0), under
// its own weight; the boundaries are set per test.
inline constexpr double kBlockDensity = 2000, kGravity = 9.81, kBlockHeight = 2.0;
inline const std::string kBlock = R"(name: block
analysis: implicit_quasistatic
grid:
  origin: [0, 0]
  extent: [1, 3]
  cell_size: 0.125
materials:
  - {name: soil, model: linear_elastic, density: 2000, youngs_modulus: 1.0e7, poisson_ratio: 0.3}
bodies:
  - {name: block, material: soil, shape: rectangle, min: [0, 0], max: [1, 2]}
gravity: [0, -9.81]
time: {end_time: 1, dt: 1}
output: {every_steps: 1}
)";

inline std::string read_text(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

inline nlohmann::json read_json(const fs::path& file) {
  return nlohmann::json::parse(read_text(file));
}

/// A fresh temporary directory per test, removed at the end.
class Implicit : public talus::test_support::TemporaryDirectoryTest {
protected:
  /// Reads `text` with `overrides` and runs it in-process into root/<dir>.
  talus::RunResult run(const std::string& text, const std::vector<std::string>& overrides,
                       const std::string& dir) {
    const talus::CaseSpec spec = talus::read_case_text(text, "case.yaml", overrides);
    talus::RunOptions options;
    options.out_dir = root_ / dir;
    options.progress = false;
    return talus::run_case(spec, options);
  }
};

/// Mean displacement (first to last frame) of the points with the largest initial x.
inline Eigen::Vector2d tip_column_displacement(const ResultsReader& results, double* tip_x) {
  Index rows = 0, cols = 0;
  const auto x0 = results.read(0, "position", &rows, &cols);
  const auto x1 = results.read(results.frame_count() - 1, "position", &rows, &cols);
  double xmax = -1e300;
  for (Index p = 0; p < rows; ++p)
    xmax = std::max(xmax, x0[static_cast<std::size_t>(2 * p)]);
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  int n = 0;
  for (Index p = 0; p < rows; ++p) {
    const auto i = static_cast<std::size_t>(2 * p);
    if (std::abs(x0[i] - xmax) < 1e-9) {
      sum += Eigen::Vector2d(x1[i] - x0[i], x1[i + 1] - x0[i + 1]);
      ++n;
    }
  }
  *tip_x = xmax;
  return n > 0 ? Eigen::Vector2d(sum / n) : Eigen::Vector2d(0, 0);
}

inline bool is_direct(const std::string& name) {
  return name == "cholmod" || name == "umfpack" || name == "klu";
}

/// Runs the `talus` binary with `args` in `cwd`; stdout/stderr go to files in `cwd`.
struct CliOutcome {
  int exit_code = -1;
  std::string out, err;
};
inline CliOutcome run_cli(const std::vector<std::string>& args, const fs::path& cwd) {
  std::string command = "cd '" + cwd.string() + "' && '" + std::string(TALUS_BINARY) + "'";
  for (const auto& a : args)
    command += " '" + a + "'"; // no argument below contains a single quote
  command += " >stdout.txt 2>stderr.txt </dev/null";
  const int status = std::system(command.c_str());
  CliOutcome o;
  o.exit_code = (status != -1 && WIFEXITED(status)) ? WEXITSTATUS(status) : -1;
  o.out = read_text(cwd / "stdout.txt");
  o.err = read_text(cwd / "stderr.txt");
  return o;
}

} // namespace talus::implicit_test
