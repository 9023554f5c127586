// Pre-run adaptive discretisation: bodies[].refine (finer lattice in the cells of the boxes;
// the refined body keeps its area exactly: every sub-cell area is a power-of-two-free
// h^2 / n^2, so the sum is compared to round-off of a few hundred additions, 1e-12 relative),
// its input errors, and `talus adapt` end to end on a small collapsing column, in 2D and 3D.
#include "talus/adapt/adapt.hpp"
#include "talus/core/errors.hpp"
#include "talus/io/case_reader.hpp"
#include "talus/scene/scene.hpp"
#include "temporary_directory.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

namespace talus {
namespace {

namespace fs = std::filesystem;

// A small Mohr-Coulomb column (0.4 m x 0.8 m, h = 0.1 m, one point per cell) slumping for
// 0.2 s: its foot yields, its top does not.
const std::string kColumn = R"(name: small_column
analysis: explicit
grid: {origin: [0, 0], extent: [1.2, 1], cell_size: 0.1}
materials:
  - {name: soil, model: mohr_coulomb, density: 1000, youngs_modulus: 2.0e6, poisson_ratio: 0.3,
     cohesion: 500, friction_angle: 30, dilation_angle: 0}
bodies:
  - {name: column, material: soil, shape: rectangle, min: [0, 0], max: [0.4, 0.8],
     particles_per_cell: 1, initial_stress: {type: geostatic}}
gravity: [0, -9.81]
boundaries: {x_min: roller, y_min: fixed}
time: {end_time: 0.2, cfl: 0.5}
)";

TEST(Refine, FinerPointsInTheBoxesAndTheSameArea) {
  const CaseSpec spec = read_case_text(
      kColumn, "column.yaml",
      {"bodies.column.refine={particles_per_cell: 3, boxes: [[0, 0, 0.2, 0.3], [0.3, 0.5, 0.4, "
       "0.6]]}"});
  const Scene<2> scene = build_scene<2>(spec);
  const auto& P = scene.particles;
  // 32 cells: 6 + 1 refined to 9 points each, 25 with one point.
  EXPECT_EQ(P.size(), 7 * 9 + 25);
  double area = 0;
  for (std::size_t p = 0; p < P.x.size(); ++p) {
    area += P.volume0[p];
    const bool refined = (P.x[p].x() < 0.2 && P.x[p].y() < 0.3) ||
                         (P.x[p].x() > 0.3 && P.x[p].y() > 0.5 && P.x[p].y() < 0.6);
    EXPECT_NEAR(P.half_size0[p].x(), refined ? 0.05 / 3 : 0.05, 1e-15) << "point " << p;
    EXPECT_NEAR(P.mass[p], 1000 * P.volume0[p], 1e-12);
  }
  EXPECT_NEAR(area, 0.4 * 0.8, 1e-12 * 0.32);
}

TEST(Refine, BadValuesAreInputErrorsAtTheirKey) {
  const struct {
    std::string set, key;
  } bad[] = {
      {"{particles_per_cell: 0, boxes: []}", "bodies[0].refine.particles_per_cell"},
      {"{particles_per_cell: 2, boxes: [[0, 0, 1]]}", "bodies[0].refine.boxes[0]"},
      {"{particles_per_cell: 2, boxes: [[0, 0.5, 1, 0.4]]}", "bodies[0].refine.boxes[0]"},
      {"{boxes: []}", "bodies[0].refine"},
  };
  for (const auto& b : bad) {
    try {
      read_case_text(kColumn, "column.yaml", {"bodies.column.refine=" + b.set});
      ADD_FAILURE() << "accepted " << b.set;
    } catch (const InputError& e) {
      EXPECT_EQ(e.where().key_path, b.key) << e.what();
    }
  }
}

class AdaptRun : public talus::test_support::TemporaryDirectoryTest {
protected:
  void SetUp() override {
    TemporaryDirectoryTest::SetUp();
    if (HasFatalFailure())
      return;
    std::ofstream(root_ / "column.yaml") << kColumn;
  }
};

// The pre-run marks the yielded foot but not the whole column; the adapted run has more points
// than the coarse one and fewer than the uniform fine one, and the report names all three.
TEST_F(AdaptRun, MarksTheYieldedCellsAndRunsAllThree) {
  AdaptOptions options;
  options.out_dir = root_ / "adapt";
  options.progress = false;
  options.benchmark = true;
  options.plastic_strain = 1e-3;
  options.buffer_cells = 0;
  const AdaptReport report = adapt_case((root_ / "column.yaml").string(), {}, options);
  ASSERT_EQ(report.runs.size(), 3u);
  EXPECT_EQ(report.body_cells, 32);
  EXPECT_GT(report.marked_cells, 0);
  EXPECT_LT(report.marked_cells, report.body_cells);
  const Index coarse = report.runs[0].particles_initial;
  const Index adapted = report.runs[1].particles_initial;
  const Index fine = report.runs[2].particles_initial;
  EXPECT_EQ(coarse, 32);
  EXPECT_EQ(fine, 4 * 32);
  EXPECT_EQ(adapted, coarse + 3 * report.marked_cells);
  for (const char* label : {"coarse", "adapted", "fine"})
    EXPECT_TRUE(fs::exists(options.out_dir / label / "run.h5")) << label;
  EXPECT_TRUE(fs::exists(options.out_dir / "adapt.md"));
  const std::string table = adapt_table(report);
  EXPECT_NE(table.find("| fine |"), std::string::npos) << table;
  // The adapted case is the case file with the recorded overrides: it builds the same points.
  const Scene<2> again =
      build_scene<2>(read_case_file((root_ / "column.yaml").string(), report.overrides));
  EXPECT_EQ(again.particles.size(), adapted);
}

// The same workflow in 3D: the column as a slab two cells deep between z rollers; refinement
// boxes are [x_min, y_min, z_min, x_max, y_max, z_max] and a marked cell gains 2^3 - 1 points.
TEST_F(AdaptRun, MarksAndRefinesA3DColumn) {
  const std::string column_3d = R"(name: small_column_3d
analysis: explicit
dimension: 3
grid: {origin: [0, 0, 0], extent: [1.2, 1, 0.2], cell_size: 0.1}
materials:
  - {name: soil, model: mohr_coulomb, density: 1000, youngs_modulus: 2.0e6, poisson_ratio: 0.3,
     cohesion: 500, friction_angle: 30, dilation_angle: 0}
bodies:
  - {name: column, material: soil, shape: box, min: [0, 0, 0], max: [0.4, 0.8, 0.2],
     particles_per_cell: 1, initial_stress: {type: geostatic}}
gravity: [0, -9.81, 0]
boundaries: {x_min: roller, y_min: fixed, z_min: roller, z_max: roller}
time: {end_time: 0.2, cfl: 0.5}
)";
  std::ofstream(root_ / "column_3d.yaml") << column_3d;
  AdaptOptions options;
  options.out_dir = root_ / "adapt_3d";
  options.progress = false;
  options.benchmark = true;
  options.plastic_strain = 1e-3;
  options.buffer_cells = 0;
  const AdaptReport report = adapt_case((root_ / "column_3d.yaml").string(), {}, options);
  ASSERT_EQ(report.runs.size(), 3u);
  EXPECT_EQ(report.body_cells, 64);
  EXPECT_GT(report.marked_cells, 0);
  EXPECT_LT(report.marked_cells, report.body_cells);
  // The slab between rollers is the 2D column twice: both z layers mark alike.
  EXPECT_EQ(report.marked_cells % 2, 0);
  EXPECT_EQ(report.runs[0].particles_initial, 64);
  EXPECT_EQ(report.runs[2].particles_initial, 8 * 64);
  EXPECT_EQ(report.runs[1].particles_initial, 64 + 7 * report.marked_cells);
  const Scene<3> again =
      build_scene<3>(read_case_file((root_ / "column_3d.yaml").string(), report.overrides));
  EXPECT_EQ(again.particles.size(), report.runs[1].particles_initial);
}

TEST_F(AdaptRun, RefusesBadOptionsBeforeRunning) {
  AdaptOptions options;
  options.out_dir = root_ / "adapt";
  options.factor = 1;
  EXPECT_THROW(adapt_case((root_ / "column.yaml").string(), {}, options), InputError);
  options.factor = 32;
  EXPECT_THROW(adapt_case((root_ / "column.yaml").string(), {}, options), InputError);
  EXPECT_FALSE(fs::exists(options.out_dir));
}

} // namespace
} // namespace talus
