// Distributed implicit runs (issue 19) through the real binary: `mpirun -np 2 talus run CASE`
// against `talus run CASE`. Each rank assembles its own points' residual and tangent on the
// unknowns it sees; Tpetra adds the shares on the owners' rows and Belos with MueLu solves,
// inside one Newton iteration (KINSOL on MPI vectors). The serial run solves with the case's
// direct solver, so the two differ by what each linear solve leaves (a relative residual of
// 1e-10) carried through Newton: the tolerances below are set from the measured differences.
// Newton itself must take the same path: the same load steps, and per step the same number of
// iterations within one.
#include "mpi_fixture.hpp"

#include <sstream>

using namespace talus::test_support;
using talus::Index;

namespace {

/// Per load step of newton.log: (step, converged, iterations).
struct NewtonLine {
  long step = 0;
  std::string converged;
  int iterations = 0;
};

std::vector<NewtonLine> newton_log(const fs::path& dir) {
  std::ifstream in(dir / "newton.log");
  std::vector<NewtonLine> out;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#')
      continue;
    std::istringstream fields(line);
    NewtonLine l;
    double t_end = 0, dt = 0;
    fields >> l.step >> t_end >> dt >> l.converged >> l.iterations;
    out.push_back(l);
  }
  return out;
}

/// Per trial of fos.csv: (factor, failed) (the first fields; the last, the reason, is text).
std::vector<std::pair<double, int>> trial_outcomes(const fs::path& dir) {
  std::ifstream in(dir / "fos.csv");
  std::vector<std::pair<double, int>> out;
  std::string line;
  std::getline(in, line); // header
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    std::string trial, factor, failed;
    std::getline(fields, trial, ',');
    std::getline(fields, factor, ',');
    std::getline(fields, failed, ',');
    out.emplace_back(std::stod(factor), std::stoi(failed));
  }
  return out;
}

class MpiImplicit : public Mpi {
protected:
  /// expect_agree, and the displacements (position minus the first frame's) agree to
  /// `relative` of the largest displacement of the run: a quasi-static run moves its points
  /// little against their coordinates, which the positions' own scale would hide.
  void expect_agree_with_displacements(double relative) {
    expect_agree(relative);
    const talus::ResultsReader a(work() / "serial" / "run.h5");
    const talus::ResultsReader b(work() / "distributed" / "run.h5");
    ASSERT_EQ(a.frame_count(), b.frame_count());
    Index rows = 0, cols = 0;
    const std::vector<double> x0 = a.read(0, "position", &rows, &cols);
    double largest = 0, worst = 0;
    for (Index f = 0; f < a.frame_count(); ++f) {
      const std::vector<double> xa = a.read(f, "position", &rows, &cols);
      const std::vector<double> xb = b.read(f, "position", &rows, &cols);
      ASSERT_EQ(xa.size(), xb.size());
      for (std::size_t i = 0; i < xa.size(); ++i) {
        largest = std::max(largest, std::abs(xa[i] - x0[i]));
        worst = std::max(worst, std::abs(xa[i] - xb[i]));
      }
    }
    ASSERT_GT(largest, 0);
    EXPECT_LE(worst, relative * largest) << "displacements differ by " << worst / largest
                                         << " of the largest displacement " << largest;
  }

  /// The serial and the distributed run took the same load steps, and each step's Newton
  /// iterations agree within `per_step` (negative: not compared).
  void expect_same_newton_path(int per_step = 1) {
    const auto serial = newton_log(work() / "serial");
    const auto distributed = newton_log(work() / "distributed");
    ASSERT_FALSE(serial.empty());
    ASSERT_EQ(serial.size(), distributed.size());
    for (std::size_t k = 0; k < serial.size(); ++k) {
      EXPECT_EQ(serial[k].step, distributed[k].step) << "line " << k;
      EXPECT_EQ(serial[k].converged, distributed[k].converged) << "step " << serial[k].step;
      if (per_step >= 0) {
        EXPECT_LE(std::abs(serial[k].iterations - distributed[k].iterations), per_step)
            << "step " << serial[k].step;
      }
    }
  }
};

// The large-deflection cantilever (Hencky, GIMP, 50 load steps, the ghost penalty on its cut
// cells): the beam bends through the cut between the ranks' boxes, its points migrate, and
// ghost-penalty faces straddle the cut. Measured 1.5e-12 (an energy; displacements 2e-15 of the
// largest); 5e-12 allows 3x. Checked that it fails: the ghost faces at the cut dropped, or
// assembled by every rank that sees them, leave the first step's tangent too ill-conditioned
// for CG (the run stops).
TEST_F(MpiImplicit, LargeDeflectionCantileverEqualsTheSerialRun) {
  run_both(kCases / "cantilever_large.yaml", {}, 2);
  expect_agree_with_displacements(5e-12);
  expect_same_newton_path();
  const auto summary = summary_of(work() / "distributed");
  EXPECT_EQ(summary.at("unknowns_last_step"),
            summary_of(work() / "serial").at("unknowns_last_step"));
  EXPECT_GT(summary.at("points_migrated").get<double>(), 0);
}

// The 3D cantilever (coarsened to 4 cells through the depth: 4096 points), pinned by two
// prescribed lines and a roller: the 3D partition, the prescribed components' reactions summed
// over the ranks. Measured 5.4e-11 (displacements 2.6e-12); 2e-10 allows 4x.
TEST_F(MpiImplicit, Cantilever3dEqualsTheSerialRun) {
  run_both(fs::path(TALUS_SOURCE_DIR) / "verification" / "cantilever_3d.yaml",
           {"grid.cell_size=0.25"}, 2);
  expect_agree_with_displacements(2e-10);
  expect_same_newton_path();
}

// The strip footing (Tresca, F-bar, a prescribed footing displacement): the F-bar cells never
// split between ranks, the prescribed motion sets Newton's force scale on every rank, and the
// footing's reaction is the sum of the ranks' shares. Shortened to a quarter of the case's
// settlement. Measured 4.0e-10 (a velocity; displacements 1.7e-10 of the largest) on the CI
// machine and 2.3e-9 (a stress) on another CPU, whose sparse kernels round differently: both
// runs stop at Newton's tolerance, 1e-8 of the force scale, so 1e-8 is the bound the solves
// guarantee (a rank's share lost or counted twice moves the stress by percents). Newton's path is
// compared by its load steps only: a Tresca return decides yield by a comparison, so the iterates
// of any two linear solvers part after the first iteration (per step, serial UMFPACK 22 9 7 7 8 7 7
// 7 7 9, serial GMRES 19 9 7 7 8 7 7 7 7 8, two ranks 19 9 7 8 8 7 8 6 7 8) and meet at the
// solution.
TEST_F(MpiImplicit, StripFootingEqualsTheSerialRun) {
  run_both(kCases / "strip_footing.yaml", {"time.end_time=0.25"}, 2);
  expect_agree_with_displacements(1e-8);
  expect_same_newton_path(-1);
}

// Terzaghi's consolidation (verification/terzaghi.yaml: H/16, an undrained load step and 100
// steps of drainage): the pore pressure's unknowns numbered across the ranks, the projected
// nodal pressure and the drained nodes (the free surface found from the points) as halo sums,
// the pressure projection's cells whole on each rank, the u-p system solved by GMRES. Measured:
// displacements 4.9e-12 of the largest, pore pressure 7.4e-12, stress 1.5e-11, velocity 5.5e-11
// (a pseudo-rate); 2e-10 allows 4x.
TEST_F(MpiImplicit, ConsolidationEqualsTheSerialRun) {
  run_both(fs::path(TALUS_SOURCE_DIR) / "verification" / "terzaghi.yaml",
           {"output.fields=[velocity, mass, volume, stress, pore_pressure]"}, 2);
  expect_agree_with_displacements(2e-10);
  expect_same_newton_path();
}

// Griffiths & Lane's slope by strength reduction on two ranks (at h = 1 m, twice the case's
// cell, to keep the test short). A trial stands or fails as in the serial search unless its
// factor lies within the search's tolerance of the factor of safety: there the outcome depends
// on the digits each linear solver leaves (a direct solver serially, Belos distributed; with
// F-bar at h = 1 the trial at 1.484 stood serially and failed on two ranks). So the two factors
// of safety agree within the tolerance, and the trials farther from it agree exactly (measured
// at h = 1 with quadratic B-splines: all eight alike, 1.4766 both, Newton iterations per trial
// within one).
TEST_F(MpiImplicit, GriffithsLaneFactorOfSafetyIsTheSerialOne) {
  const std::string case_file = (kCases / "slope_griffiths_lane.yaml").string();
  const std::vector<std::string> args = {"fos",   case_file,          "--threads", "1",
                                         "--set", "grid.cell_size=1", "--out"};
  const Outcome serial = talus(appended(args, {"serial"}));
  ASSERT_EQ(serial.exit_code, 0) << serial.describe();
  const Outcome distributed = mpirun(2, appended(args, {"distributed"}));
  ASSERT_EQ(distributed.exit_code, 0) << distributed.describe();
  std::ifstream ja(work() / "serial" / "fos.json"), jb(work() / "distributed" / "fos.json");
  const auto fa = nlohmann::json::parse(ja), fb = nlohmann::json::parse(jb);
  const double tolerance = 0.02; // the case's strength_reduction.tolerance
  const double fos = fa.at("factor_of_safety").get<double>();
  EXPECT_NEAR(fb.at("factor_of_safety").get<double>(), fos, tolerance);
  const auto a = trial_outcomes(work() / "serial"), b = trial_outcomes(work() / "distributed");
  ASSERT_GE(a.size(), 6u);
  std::size_t compared = 0;
  // The searches run the same factors until an outcome near the factor of safety parts them.
  for (std::size_t k = 0; k < std::min(a.size(), b.size()) && a[k].first == b[k].first; ++k)
    if (std::abs(a[k].first - fos) > tolerance) {
      EXPECT_EQ(a[k].second, b[k].second) << "trial " << k + 1 << " at F = " << a[k].first;
      ++compared;
    }
  EXPECT_GE(compared, 4u);
  // One line of output, from rank 0.
  EXPECT_EQ(std::count(distributed.out.begin(), distributed.out.end(), '\n'),
            std::count(serial.out.begin(), serial.out.end(), '\n'));
}

// SIGTERM to one rank of the large-deflection cantilever after ten load steps: the checkpoint
// holds the line-search choice and the prescribed fraction with the points, and the run resumes
// on two ranks or on one as the serial run ends (manually measured 8.5e-14 and 7.8e-14 of the
// field scales; the bound as for the uninterrupted run).
TEST_F(MpiImplicit, AnInterruptedImplicitRunResumesOnAnyNumberOfRanks) {
  const std::string case_file = (kCases / "cantilever_large.yaml").string();
  const std::vector<std::string> common = {"--threads", "1", "--set",
                                           "output.checkpoint.every_steps=5"};
  auto args = [&](const std::vector<std::string>& head) { return appended(head, common); };
  const Outcome serial = talus(args({"run", case_file, "--out", "serial"}));
  ASSERT_EQ(serial.exit_code, 0) << serial.describe();
  interrupt_one_rank(args({"run", case_file, "--out", "killed"}), "killed", 12);
  ASSERT_TRUE(fs::exists(work() / "killed" / "checkpoints"));
  fs::copy(work() / "killed", work() / "killed_serial", fs::copy_options::recursive);
  const Outcome on_two = mpirun(2, args({"run", case_file, "--resume", "killed"}));
  ASSERT_EQ(on_two.exit_code, 0) << on_two.describe();
  expect_agree(5e-12, "killed");
  const Outcome on_one = talus(args({"run", case_file, "--resume", "killed_serial"}));
  ASSERT_EQ(on_one.exit_code, 0) << on_one.describe();
  expect_agree(5e-12, "killed_serial");
}

// What does not run distributed is refused before anything is written (exit 2).
TEST_F(MpiImplicit, RefusesWhatItCannotDistribute) {
  const Outcome r = mpirun(2, {"run", (kCases / "cantilever.yaml").string(), "--out", "refused",
                               "--dump-tangent", "K.mtx"});
  EXPECT_EQ(r.exit_code, 2) << r.describe();
  EXPECT_NE(r.err.find("does not run distributed yet"), std::string::npos) << r.describe();
  EXPECT_FALSE(fs::exists(work() / "refused"));
  const Outcome adapt = mpirun(2, {"adapt", (kCases / "cantilever.yaml").string()});
  EXPECT_EQ(adapt.exit_code, 2) << adapt.describe();
  EXPECT_NE(adapt.err.find("talus adapt does not run under mpirun"), std::string::npos)
      << adapt.describe();
  // A platen's shared unknown would span the ranks.
  const fs::path mandel = fs::path(TALUS_SOURCE_DIR) / "verification" / "mandel.yaml";
  const Outcome platen = mpirun(2, {"run", mandel.string(), "--out", "platen"});
  EXPECT_EQ(platen.exit_code, 2) << platen.describe();
  EXPECT_NE(platen.err.find("a platen (boundaries.y_max) does not run distributed yet"),
            std::string::npos)
      << platen.describe();
  EXPECT_FALSE(fs::exists(work() / "platen"));
}

} // namespace
