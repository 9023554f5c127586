// The factor of safety of a staged case (issue 40, step 6): what the reader takes and refuses in
// strength_reduction with stages, at the key; and the undrained stages of the reduction's
// ramps: a stage without flow leaves each point's pore pressure as it found it, where the same
// stage with flow drains the column.
#include "talus/core/errors.hpp"
#include "talus/io/case_reader.hpp"
#include "talus/io/results.hpp"
#include "talus/solver/run.hpp"
#include "talus/solver/strength_reduction.hpp"

#include "cli_support.hpp"
#include "scene_error_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace {

using namespace talus;
using talus::test_support::has;
using talus::test_support::scene_error_of;

/// A clay column 1 m high and 0.25 m wide under q = 1 kPa put on undrained (1e-6 s), then held
/// for 1 s: E = 10 MPa, nu = 0, k = 1e-3 m/s: c_v = 1 m^2/s, T_v = 1 at the hold's end, the top
/// drained. `model` and `strength` make it frictional; `extra` is appended at the end.
std::string column(const std::string& model = "linear_elastic", const std::string& strength = "",
                   const std::string& extra = "",
                   const std::string& hold = "time: {end_time: 1, dt: 0.25}") {
  return "name: clay\n"
         "grid: {origin: [0, 0], extent: [0.25, 1.25], cell_size: 0.125}\n"
         "water: {unit_weight: 1.0e4}\n"
         "materials:\n"
         "  - {name: clay, model: " +
         model + ", density: 2000, youngs_modulus: 1.0e7, poisson_ratio: 0, permeability: 1.0e-3" +
         strength +
         "}\n"
         "bodies:\n"
         "  - {name: column, material: clay, shape: rectangle, min: [0, 0], max: [0.25, 1], "
         "particles_per_cell: 2}\n"
         "tractions:\n"
         "  - {body: column, side: top, traction: [0, -1.0e3]}\n"
         "boundaries: {x_min: roller, x_max: roller, y_min: roller}\n"
         "stages:\n"
         "  - {name: load, analysis: implicit_quasistatic, time: {end_time: 1.0e-6, dt: 1.0e-6}}\n"
         "  - {name: hold, analysis: implicit_quasistatic, " +
         hold +
         "}\n"
         "output: {every_steps: 1, fields: [pore_pressure]}\n"
         "probes:\n"
         "  - {name: top, point: [0.125, 0.9375]}\n"
         "solver: {shape: linear}\n"
         "silence_warnings: [consolidation_step]\n" +
         extra;
}

std::string frictional(const std::string& reduction,
                       const std::string& hold = "time: {end_time: 1, dt: 0.25}") {
  return column("mohr_coulomb", ", cohesion: 1.0e4, friction_angle: 30", reduction, hold);
}

TEST(FosHistoryInput, AStagedCaseIsSearchedAfterItsStagesIncrementally) {
  const CaseSpec all = read_case_text(
      frictional("strength_reduction: {probe: top, mode: incremental}\n"), "case.yaml");
  EXPECT_EQ(all.strength_reduction->after_stages, (std::vector<std::size_t>{0, 1}));
  const CaseSpec one = read_case_text(
      frictional("strength_reduction: {probe: top, mode: incremental, after: [hold]}\n"),
      "case.yaml");
  EXPECT_EQ(one.strength_reduction->after_stages, (std::vector<std::size_t>{1}));

  struct Bad {
    std::string text, key, message;
  };
  std::string unstaged = frictional("strength_reduction: {probe: top, after: [load]}\n");
  unstaged.replace(unstaged.find("stages:\n"), unstaged.find("output:") - unstaged.find("stages:"),
                   "analysis: implicit_quasistatic\ntime: {end_time: 1, dt: 1}\n");
  const std::vector<Bad> cases = {
      {frictional("strength_reduction: {probe: top}\n"), "strength_reduction",
       "give 'mode: incremental'"},
      {frictional("strength_reduction: {probe: top, mode: trials}\n"), "strength_reduction.mode",
       "give 'mode: incremental'"},
      {frictional("strength_reduction: {probe: top, mode: incremental, after: [nope]}\n"),
       "strength_reduction.after[0]", "no stage named 'nope'"},
      {frictional("strength_reduction: {probe: top, mode: incremental, after: [hold, load]}\n"),
       "strength_reduction.after[1]", "in the order they run"},
      {frictional("strength_reduction: {probe: top, mode: incremental}\n",
                  "time: {end_time: 1, dt: 0.25}, strength_factor: 1.2"),
       "strength_reduction", "stage 'hold' sets a strength_factor"},
      {unstaged, "strength_reduction.after", "this case has no 'stages'"},
  };
  for (const Bad& c : cases) {
    SCOPED_TRACE(c.text);
    const InputError e = scene_error_of(c.text);
    EXPECT_EQ(e.where().key_path, c.key) << e.what();
    EXPECT_TRUE(has(e.what(), c.message)) << e.what();
  }
}

class UndrainedStage : public talus::test_support::Cli {};

/// Each point's pore pressure in frame `frame` of the run in `dir` (-1: the last).
std::vector<double> pore_pressure(const std::filesystem::path& dir, Index frame) {
  const ResultsReader results(dir / "run.h5");
  Index rows = 0, cols = 0;
  return results.read(frame < 0 ? results.frame_count() - 1 : frame, "pore_pressure", &rows, &cols);
}

// After the undrained load the points hold p close to q. A hold of T_v = 1 drains them to a mean
// below 0.3 q (the series: 0.19 q at T_v = 1; at most 0.3 for four steps of backward Euler); the
// same hold without flow leaves every point's p as the load left it: within 1e-3 q (measured
// 3.0e-4 q, the small imbalance the points' new places on the grid leave at a stage's first
// step, taken up without flow).
TEST_F(UndrainedStage, AStageWithoutFlowKeepsEachPointsPressure) {
  const auto run = [&](bool undrained, const char* out) {
    CaseSpec spec = read_case_text(column(), "case.yaml");
    spec.stages[1].undrained = undrained;
    RunOptions options;
    options.out_dir = work() / out;
    const RunResult r = run_case(spec, options);
    EXPECT_EQ(r.status, "completed") << r.message;
  };
  run(false, "draining");
  run(true, "undrained");
  const std::vector<double> loaded = pore_pressure(work() / "undrained", 1);
  const std::vector<double> draining = pore_pressure(work() / "draining", -1);
  const std::vector<double> undrained = pore_pressure(work() / "undrained", -1);
  ASSERT_EQ(loaded.size(), undrained.size());
  double mean_loaded = 0, mean_draining = 0, moved = 0;
  for (std::size_t s = 0; s < loaded.size(); ++s) {
    moved = std::max(moved, std::abs(undrained[s] - loaded[s]) / 1e3);
    mean_loaded += loaded[s] / static_cast<double>(loaded.size());
    mean_draining += draining[s] / static_cast<double>(loaded.size());
  }
  EXPECT_LT(moved, 1e-3) << "the largest change of p over q";
  EXPECT_GT(mean_loaded, 0.9e3);
  EXPECT_LT(mean_draining, 0.3e3);
}

} // namespace

namespace {

// The incremental search of a consolidation case is undrained: a dilatant material gains
// strength from suction, and the search says so, naming it; ψ = 0 and a dry case do not warn.
// Davis's flow rule makes every reduced material associated, so it warns at ψ = 0 too.
TEST(FosHistoryInput, AnUndrainedSearchWarnsOfDilatantMaterials) {
  const std::string reduction = "strength_reduction: {probe: top, mode: incremental}\n";
  const std::string dilatant = column(
      "mohr_coulomb", ", cohesion: 1.0e4, friction_angle: 30, dilation_angle: 10", reduction);
  const auto warning = undrained_dilatancy_warning(read_case_text(dilatant, "case.yaml"));
  ASSERT_TRUE(warning.has_value());
  EXPECT_TRUE(has(*warning, "'clay' (dilation angle 10 deg)")) << *warning;
  EXPECT_FALSE(undrained_dilatancy_warning(read_case_text(frictional(reduction), "case.yaml")));
  const std::string davis =
      "strength_reduction: {probe: top, mode: incremental, flow_rule: davis}\n";
  EXPECT_TRUE(undrained_dilatancy_warning(read_case_text(frictional(davis), "case.yaml")));
  CaseSpec dry = read_case_text(dilatant, "case.yaml");
  for (MaterialSpec& m : dry.materials)
    m.flow.reset(); // no consolidation: the reduction is drained
  EXPECT_FALSE(undrained_dilatancy_warning(dry));
}

} // namespace
