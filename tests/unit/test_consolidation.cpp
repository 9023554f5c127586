// Consolidation (issue 40, step 3): what the reader takes and refuses for a material's pore
// flow and the water's drained faces, at the key; and what a coupled step does in the small:
// an undrained step carries a load on the pore water, an infinitely long one is the drained
// answer, and a column that drains keeps its water's volume balance.
#include "talus/core/errors.hpp"
#include "talus/io/case_reader.hpp"
#include "talus/io/results.hpp"
#include "talus/scene/scene.hpp"

#include "cli_support.hpp"
#include "scene_error_support.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace {

using namespace talus;
using talus::test_support::has;
using talus::test_support::scene_error_of;
using talus::test_support::write_file;

/// A clay column 1 m high and 0.25 m wide, loaded by q = 1 kPa on its top: one stage of
/// `load_time` (in `steps` steps) with the load ramped, then a hold of `hold_time`.
/// E = 10 MPa, nu = 0: c_v = k E / gamma_w = 1 m^2/s.
std::string column(const std::string& water = "water: {unit_weight: 1.0e4}",
                   const std::string& material_extra = ", permeability: 1.0e-3",
                   const std::string& stages =
                       "stages:\n"
                       "  - {name: load, analysis: implicit_quasistatic, time: {end_time: 1.0e-6, "
                       "dt: 1.0e-6}}\n") {
  return "name: clay\n"
         "grid: {origin: [0, 0], extent: [0.25, 1.25], cell_size: 0.125}\n" +
         water +
         "\nmaterials:\n"
         "  - {name: clay, model: linear_elastic, density: 2000, youngs_modulus: 1.0e7, "
         "poisson_ratio: 0" +
         material_extra +
         "}\n"
         "bodies:\n"
         "  - {name: column, material: clay, shape: rectangle, min: [0, 0], max: [0.25, 1], "
         "particles_per_cell: 2}\n"
         "tractions:\n"
         "  - {body: column, side: top, traction: [0, -1.0e3]}\n"
         "boundaries: {x_min: roller, x_max: roller, y_min: roller}\n" +
         stages + "output: {every_steps: 1, fields: [volume, stress, " +
         (water.empty() ? "" : "pore_pressure, ") +
         "reference_position]}\n"
         "solver: {shape: linear}\n";
}

TEST(ConsolidationInput, ReadsThePoreFlowAndTheDrainedFaces) {
  const CaseSpec spec = read_case_text(
      column("water: {unit_weight: 1.0e4, drained: [y_min, x_max]}",
             ", permeability: 1.0e-3, biot_coefficient: 0.6, fluid_bulk_modulus: 2.0e9, "
             "porosity: 0.4"),
      "case.yaml");
  ASSERT_TRUE(spec.consolidates());
  const PoreFlowSpec& f = *spec.materials[0].flow;
  EXPECT_EQ(f.permeability, 1.0e-3);
  EXPECT_EQ(f.biot_coefficient, 0.6);
  // 1/M = n / K_f + (alpha - n)(1 - alpha) / K, K = E / 3 (nu = 0).
  EXPECT_DOUBLE_EQ(f.inverse_biot_modulus, 0.4 / 2.0e9 + 0.2 * 0.4 / (1.0e7 / 3));
  EXPECT_TRUE(spec.water->phreatic.empty());
  EXPECT_TRUE(spec.water->drained[2] && spec.water->drained[1]);
  EXPECT_FALSE(spec.water->drained[0] || spec.water->drained[3]);
  // A dry case and a case with water at rest do not consolidate.
  EXPECT_FALSE(read_case_text(column("", ""), "case.yaml").consolidates());
}

TEST(ConsolidationInput, BadPoreFlowIsRefusedAtItsKey) {
  struct Bad {
    std::string text, key, message;
  };
  const std::string explicit_stage =
      "stages:\n  - {name: load, analysis: explicit, time: {end_time: 1.0e-6, dt: 1.0e-7}}\n";
  const std::vector<Bad> cases = {
      {column("", ", permeability: 1.0e-3"), "materials[0]", "has no water section"},
      {column("water: {unit_weight: 1.0e4}", ", permeability: 0"), "materials[0].permeability",
       "must be > 0"},
      {column("water: {unit_weight: 1.0e4}", ", biot_modulus: 1.0e9"), "materials[0].biot_modulus",
       "give the material's permeability"},
      {column("water: {unit_weight: 1.0e4}", ", permeability: 1.0e-3, biot_coefficient: 1.5"),
       "materials[0].biot_coefficient", "must be in (0, 1]"},
      {column("water: {unit_weight: 1.0e4}", ", permeability: 1.0e-3, porosity: 0.3"),
       "materials[0].porosity", "fluid_bulk_modulus and porosity go together"},
      {column("water: {unit_weight: 1.0e4}",
              ", permeability: 1.0e-3, biot_modulus: 1.0e9, porosity: 0.3, fluid_bulk_modulus: "
              "2.0e9"),
       "materials[0].biot_modulus", "give the storage once"},
      {column("water: {unit_weight: 1.0e4}",
              ", permeability: 1.0e-3, biot_coefficient: 0.5, porosity: 0.7, "
              "fluid_bulk_modulus: 1.0e20"),
       "materials[0].porosity", "the porosity cannot exceed alpha"},
      {column("water: {unit_weight: 1.0e4, drained: [top]}"), "water.drained[0]",
       "a drained face is one of the grid's faces"},
      {column("water: {unit_weight: 1.0e4}", ", permeability: 1.0e-3", explicit_stage), "stages[0]",
       "use analysis: implicit_quasistatic"},
      {column("water: {unit_weight: 1.0e4}", ""), "water", "give the phreatic surface"},
  };
  for (const Bad& c : cases) {
    SCOPED_TRACE(c.text);
    const InputError e = scene_error_of(c.text);
    EXPECT_EQ(e.where().key_path, c.key) << e.what();
    EXPECT_TRUE(has(e.what(), c.message)) << e.what();
  }
  // The stabilisation of a pore pressure that a dry case does not have.
  std::string dry = column("", "");
  dry.replace(dry.find("solver: {shape: linear}"), 23,
              "solver: {shape: linear, pressure_projection: 1}");
  const InputError e = scene_error_of(dry);
  EXPECT_EQ(e.where().key_path, "solver.pressure_projection") << e.what();
  EXPECT_TRUE(has(e.what(), "this case has none")) << e.what();
}

class ConsolidationRun : public talus::test_support::Cli {};

/// The volume-weighted mean pore pressure and the mean settlement of the top layer of points
/// in the run's last frame.
struct ColumnState {
  double mean_pressure = 0, settlement = 0;
};
ColumnState last_state(const std::filesystem::path& h5) {
  const ResultsReader results(h5);
  const Index last = results.frame_count() - 1;
  Index rows = 0, dims = 0, cols = 0;
  const auto x0 = results.read(last, "reference_position", &rows, &dims);
  const auto x = results.read(last, "position", &rows, &dims);
  const auto volume = results.read(last, "volume", &rows, &cols);
  const auto p = results.read(last, "pore_pressure", &rows, &cols);
  double V = 0, pV = 0, top = 0, count = 0;
  for (std::size_t s = 0; s < p.size(); ++s) {
    V += volume[s];
    pV += volume[s] * p[s];
    if (x0[2 * s + 1] > 1 - 0.0625) {
      top += x0[2 * s + 1] - x[2 * s + 1];
      ++count;
    }
  }
  return {pV / V, top / count};
}

// A load put on in 1e-6 s (T_v = 1e-6) is carried by the pore water: p = q but in the drained
// top cell (the series' layer, sqrt(c_v t) = 1 mm, is far below h = H/8; the points there take
// the nodes' 0 and q: measured 1 - h / (4H)), and the skeleton has hardly moved (at most that
// cell's drained compression q h / M; measured 0.17 of it). The same load put on in one step of
// 1e6 s is the drained answer: the pressure a step that long leaves, eps gamma_w H^2 / (k dt) =
// 1e-6 q (measured 3.3e-7; bound 1e-5), and the top points, at
// Y = H - h / 4, settled q Y / M (linear elasticity; 1e-3 for the geometry's change, F - I of
// 1e-4).
TEST_F(ConsolidationRun, AnUndrainedStepLoadsTheWaterAndAnEndlessOneTheSkeleton) {
  constexpr double q = 1.0e3, h = 0.125, M = 1.0e7, top = 1 - h / 4;
  write_file(work() / "undrained.yaml", column());
  auto r = talus({"run", "undrained.yaml", "--out", "undrained"});
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  const ColumnState undrained = last_state(work() / "undrained" / "run.h5");
  EXPECT_GE(undrained.mean_pressure / q, 1 - h / 2);
  EXPECT_LE(undrained.mean_pressure / q, 1 + 1e-9);
  EXPECT_LT(std::abs(undrained.settlement), q * h / M);

  write_file(work() / "drained.yaml",
             column("water: {unit_weight: 1.0e4}", ", permeability: 1.0e-3",
                    "stages:\n  - {name: load, analysis: implicit_quasistatic, time: {end_time: "
                    "1.0e6, dt: 1.0e6}}\n"));
  r = talus({"run", "drained.yaml", "--out", "drained"});
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  const ColumnState drained = last_state(work() / "drained" / "run.h5");
  EXPECT_LT(std::abs(drained.mean_pressure) / q, 1e-5);
  EXPECT_NEAR(drained.settlement / (q * top / M), 1.0, 1e-3);
}

} // namespace

namespace {

// A first stage whose weight grows from zero grows the water's with it: the table's pressure and
// the head that drives the flow (gamma_w g / |g| in Darcy's law) alike. The column under a water
// table at its top, its weight ramped in two drained steps (T_v = 1e6 each): after the first,
// every point's p is half the hydrostatic gamma_w (H - y) within 5e-4 gamma_w H (measured
// 1.2e-4); with the full head driving the flow under half the weight the largest departure was
// 0.48, the whole hydrostatic pressure under half the weight (on a slope of Mohr-Coulomb soil
// an effective tension that yielded it).
TEST_F(ConsolidationRun, AGrowingWeightGrowsTheWatersHead) {
  std::string text = column("water: {unit_weight: 1.0e4, level: 1}", ", permeability: 1.0e-3",
                            "stages:\n  - {name: settle, analysis: implicit_quasistatic, time: "
                            "{end_time: 2.0e6, dt: 1.0e6}}\n");
  text.replace(text.find("tractions:"), text.find("boundaries:") - text.find("tractions:"),
               "gravity: [0, -10]\n");
  write_file(work() / "weight.yaml", text);
  const auto r = talus({"run", "weight.yaml", "--out", "weight"});
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  const ResultsReader results(work() / "weight" / "run.h5");
  Index rows = 0, dims = 0, cols = 0;
  const auto x = results.read(1, "position", &rows, &dims);
  const auto p = results.read(1, "pore_pressure", &rows, &cols);
  double worst = 0;
  for (std::size_t s = 0; s < p.size(); ++s)
    worst = std::max(worst, std::abs(p[s] - 0.5 * 1.0e4 * (1 - x[2 * s + 1])) / 1.0e4);
  EXPECT_LT(worst, 5e-4) << "the largest departure from half the hydrostatic pressure, / gamma_w H";
}

} // namespace
