// Restart (issue 20), end to end through the real `talus` binary: a run killed with SIGKILL at
// a random step and resumed with `--resume` ends in the state of an uninterrupted run; a
// damaged checkpoint is skipped for the one before; a full disk stops the run with a clear
// error and the earlier checkpoints intact; a changed case is refused by key.
//
// The kill step is drawn from a seeded generator between the first checkpoint and the end. The
// number of seeds is TALUS_RESTART_SEEDS (default 1: the `verification` label; the `slow`
// label runs more). Every run uses one thread: the explicit runs must then be bitwise equal.
#include "../unit/cli_support.hpp"
#include "../unit/result_comparison.hpp"

#include "talus/io/checkpoint_file.hpp"
#include "talus/io/csv.hpp"
#include "talus/io/results.hpp"

#include <sys/mount.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <random>

namespace fs = std::filesystem;
using namespace talus::test_support;
using talus::Index;

namespace {

const fs::path kCases = fs::path(TALUS_SOURCE_DIR) / "cases";

int seeds() {
  const char* text = std::getenv("TALUS_RESTART_SEEDS");
  return text ? std::max(1, std::atoi(text)) : 1;
}

/// Rows of timeseries.csv written so far (the header not counted).
Index rows_written(const fs::path& dir) {
  const std::string text = read_file(dir / "timeseries.csv");
  return std::max<Index>(0, static_cast<Index>(std::count(text.begin(), text.end(), '\n')) - 1);
}

class Restart : public Cli {
protected:
  int threads_ = 1; ///< of every run, the killed, resumed and uninterrupted alike

  /// `talus run CASE --out DIR --threads N --set ...`, to its end.
  void run_to_end(const fs::path& case_file, const std::vector<std::string>& sets,
                  const fs::path& dir) {
    const Outcome r = talus(arguments("run", case_file, sets, {"--out", dir.string()}));
    ASSERT_EQ(r.exit_code, 0) << r.describe();
  }

  /// The same run, killed with SIGKILL once timeseries.csv holds `row` rows.
  void run_and_kill(const fs::path& case_file, const std::vector<std::string>& sets,
                    const fs::path& dir, Index row) {
    ASSERT_TRUE(try_run_and_kill(case_file, sets, dir, row))
        << "the run ended before the kill at row " << row;
  }

  /// Starts the run and kills it once it has written `row` rows; false when the run ended
  /// first (on a loaded machine the poll below can sleep past the rest of a short run).
  bool try_run_and_kill(const fs::path& case_file, const std::vector<std::string>& sets,
                        const fs::path& dir, Index row) {
    Child child(arguments("run", case_file, sets, {"--out", dir.string(), "--force"}), work(),
                root_);
    EXPECT_TRUE(child.started());
    while (rows_written(dir) < row) {
      if (const auto done = child.poll()) {
        EXPECT_EQ(done->exit_code, 0) << done->describe();
        return false;
      }
      std::this_thread::sleep_for(std::chrono::microseconds(500));
    }
    ::kill(child.pid(), SIGKILL);
    const auto ended = child.wait();
    if (ended.exit_code == 0) // it finished before the kill landed
      return false;
    EXPECT_EQ(ended.exit_code, 128 + SIGKILL) << ended.describe();
    expect_frames_readable(dir);
    return true;
  }

  /// Every frame a killed run wrote reads back whole.
  static void expect_frames_readable(const fs::path& dir) {
    const talus::ResultsReader reader(dir / "run.h5");
    EXPECT_GE(reader.frame_count(), 1);
    for (Index f = 0; f < reader.frame_count(); ++f)
      for (const std::string& field : reader.frame_fields(f)) {
        Index rows = 0, cols = 0;
        EXPECT_FALSE(reader.read(f, field, &rows, &cols).empty()) << "frame " << f << " " << field;
      }
  }

  Outcome resume(const std::string& command, const fs::path& case_file,
                 const std::vector<std::string>& sets, const fs::path& dir,
                 std::vector<std::string> more = {}) {
    more.insert(more.begin(), {"--resume", dir.string()});
    return talus(arguments(command, case_file, sets, more));
  }

  /// Kills the run at random rows (one per seed) and resumes it; each must end where the
  /// uninterrupted run ended. `first_checkpoint`: the row after which a checkpoint exists.
  void kill_and_resume(const fs::path& case_file, const std::vector<std::string>& sets,
                       Index first_checkpoint, Equality eq) {
    const fs::path reference = work() / "reference";
    run_to_end(case_file, sets, reference);
    if (HasFatalFailure())
      return;
    const Index rows = rows_written(reference);
    for (int seed = 1; seed <= seeds(); ++seed) {
      std::mt19937 generator(static_cast<unsigned>(seed));
      Index row =
          std::uniform_int_distribution<Index>(first_checkpoint + 1, rows * 9 / 10)(generator);
      const fs::path dir = work() / ("killed_" + std::to_string(seed));
      // A run that ended before its kill is run again, killed halfway to the first checkpoint.
      bool killed = false;
      for (int attempt = 0; attempt < 4 && !killed && !HasFailure(); ++attempt) {
        killed = try_run_and_kill(case_file, sets, dir, row);
        if (!killed)
          row = first_checkpoint + 1 + (row - first_checkpoint - 1) / 2;
      }
      SCOPED_TRACE("seed " + std::to_string(seed) + ", killed at row " + std::to_string(row));
      ASSERT_TRUE(killed) << "every run ended before its kill";
      if (HasFatalFailure())
        return;
      const Outcome r = resume("run", case_file, sets, dir);
      ASSERT_EQ(r.exit_code, 0) << r.describe();
      EXPECT_NE(r.err.find("resuming from"), std::string::npos) << r.describe();
      expect_same_series(reference, dir, eq);
      expect_same_frames(reference, dir, eq);
      const auto a = read_json(reference / "summary.json");
      const auto b = read_json(dir / "summary.json");
      for (const char* key : {"status", "steps", "frames", "particles", "final_time"})
        EXPECT_EQ(a.at(key), b.at(key)) << key;
      for (const char* key : {"newton_iterations", "splits"}) {
        if (a.contains(key)) {
          EXPECT_EQ(a.at(key), b.at(key)) << key;
        }
      }
    }
  }

  std::vector<std::string> arguments(const std::string& command, const fs::path& case_file,
                                     const std::vector<std::string>& sets,
                                     const std::vector<std::string>& more) const {
    std::vector<std::string> args = {command, case_file.string(), "--threads",
                                     std::to_string(threads_)};
    for (const auto& s : sets)
      args.insert(args.end(), {"--set", s});
    args.insert(args.end(), more.begin(), more.end());
    return args;
  }
};

// Explicit MUSL, elastic discs.
TEST_F(Restart, ExplicitRunKilledAndResumedIsBitwiseEqual) {
  kill_and_resume(kCases / "colliding_discs.yaml",
                  {"grid.cell_size=0.0125", "output.checkpoint.every_steps=25"}, 25, {});
}

// The same on two threads, the count it is resumed with: the README's "ends bitwise" with more
// than one thread.
TEST_F(Restart, ExplicitRunOnTwoThreadsResumesBitwise) {
  threads_ = 2;
  kill_and_resume(kCases / "colliding_discs.yaml",
                  {"grid.cell_size=0.0125", "output.checkpoint.every_steps=25"}, 25, {});
}

// Explicit, Mohr-Coulomb with geostatic stress, points split, voxels written.
TEST_F(Restart, ExplicitPlasticSplittingRunResumesBitwise) {
  kill_and_resume(kCases / "soil_column_collapse.yaml",
                  {"time.end_time=1.0", "output.checkpoint.every_steps=100"}, 100, {});
}

TEST_F(Restart, ImplicitQuasiStaticRunResumesBitwise) {
  kill_and_resume(kCases / "cantilever_large.yaml", {"output.checkpoint.every_steps=3"}, 3, {});
}

// Pore water (the submerged column, 40 load steps of 4096 points): the points' pore pressure
// is in the checkpoint and the frames, and a resumed run ramps it on as the uninterrupted one.
TEST_F(Restart, ImplicitRunWithWaterResumesBitwise) {
  kill_and_resume(fs::path(TALUS_SOURCE_DIR) / "verification" / "submerged_column.yaml",
                  {"time.dt=0.025", "grid.cell_size=0.015625", "grid.extent=[0.25, 1.0625]",
                   "output.checkpoint.every_steps=2",
                   "output.fields=[velocity, stress, pore_pressure]"},
                  2, {});
}

// Consolidation (Terzaghi's column at H/64, 2048 points: an undrained load step, then 100 steps
// of drainage): each step starts from the points' pore pressure, projected on the nodes, so a
// resumed run takes it from the checkpoint and drains on as the uninterrupted one.
TEST_F(Restart, ConsolidationRunResumesBitwise) {
  kill_and_resume(fs::path(TALUS_SOURCE_DIR) / "verification" / "terzaghi.yaml",
                  {"grid.cell_size=0.015625", "grid.extent=[0.125, 1.0625]",
                   "output.checkpoint.every_steps=2",
                   "output.fields=[velocity, stress, pore_pressure]"},
                  2, {});
}

// Newmark implicit dynamics, Tresca.
TEST_F(Restart, ImplicitDynamicRunResumesBitwise) {
  kill_and_resume(kCases / "colliding_discs_tresca_implicit.yaml",
                  {"output.checkpoint.every_steps=5"}, 5, {});
}

// Two stages (quasi-static gravity, then Newmark run-out at reduced strength): the kill lands
// in either stage.
TEST_F(Restart, StagedRunWithStrengthReductionResumesBitwise) {
  kill_and_resume(
      kCases / "slope_runout.yaml",
      {"grid.cell_size=1.0", "stages[1].time.end_time=3", "output.checkpoint.every_steps=4"}, 4,
      {});
}

/// fos.csv's rows without the seconds column: the trials' factors, outcomes and what ended
/// them, stiffnesses, crest displacements, load steps, Newton iterations and cut-backs.
std::vector<std::string> fos_rows(const fs::path& dir) {
  std::vector<std::string> rows;
  std::istringstream in(read_file(dir / "fos.csv"));
  for (std::string line; std::getline(in, line);) {
    std::size_t cut = 0;
    for (int k = 0; k < 12 && cut != std::string::npos; ++k)
      cut = line.find(',', cut + 1);
    rows.push_back(line.substr(0, cut));
  }
  return rows;
}

/// The timeseries.csv of each trial fos.log lists as finished, with its last write time.
std::vector<std::pair<fs::path, fs::file_time_type>> finished_trial_files(const fs::path& dir) {
  std::vector<std::pair<fs::path, fs::file_time_type>> files;
  std::istringstream in(read_file(dir / "fos.log"));
  const std::string prefix = "trial F = ";
  for (std::string line; std::getline(in, line);)
    if (line.rfind(prefix, 0) == 0) {
      const std::string factor = line.substr(prefix.size(), line.find(':') - prefix.size());
      const fs::path file = dir / "trials" / ("F" + factor) / "timeseries.csv";
      files.emplace_back(file, fs::last_write_time(file));
    }
  return files;
}

// SIGTERM (a cluster's wall-time limit): the run stops after the step in progress with a
// checkpoint of that state and a last frame; the resumed run drops that extra frame and ends as
// the uninterrupted run, bitwise.
TEST_F(Restart, AnInterruptedRunCheckpointsAndResumesWithoutItsExtraFrame) {
  const fs::path case_file = kCases / "colliding_discs.yaml";
  const std::vector<std::string> sets = {"grid.cell_size=0.0125",
                                         "output.checkpoint.every_seconds=1000"};
  const fs::path reference = work() / "reference";
  run_to_end(case_file, sets, reference);
  const fs::path dir = work() / "interrupted";
  Child child(arguments("run", case_file, sets, {"--out", dir.string()}), work(), root_);
  while (rows_written(dir) < 300) {
    if (const auto done = child.poll())
      FAIL() << "the run ended before the interrupt:\n" << done->describe();
    std::this_thread::sleep_for(std::chrono::microseconds(500));
  }
  ::kill(child.pid(), SIGTERM);
  const Outcome stopped = child.wait();
  EXPECT_EQ(stopped.exit_code, 1) << stopped.describe();
  EXPECT_EQ(read_json(dir / "summary.json").at("status"), "interrupted");
  ASSERT_EQ(talus::list_checkpoints(dir / "checkpoints").size(), 1u);
  const Outcome r = resume("run", case_file, sets, dir);
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  expect_same_series(reference, dir, {});
  expect_same_frames(reference, dir, {});
}

// A factor-of-safety search killed during a trial: the trials that finished are kept, the one
// cut short continues from its checkpoint, and the search ends with the same trials.
TEST_F(Restart, FactorOfSafetySearchResumesKeepingFinishedTrials) {
  for (const std::string mode : {"trials", "incremental"}) {
    SCOPED_TRACE(mode);
    const std::vector<std::string> sets = {"strength_reduction.mode=" + mode,
                                           "output.checkpoint.every_steps=2"};
    const fs::path case_file = kCases / "slope_griffiths_lane.yaml";
    const fs::path reference = work() / (mode + "_reference");
    ASSERT_EQ(talus(arguments("fos", case_file, sets, {"--out", reference.string()})).exit_code, 0);
    const auto trials = static_cast<int>(read_json(reference / "fos.json").at("trials"));
    const Index rows = rows_written(reference / "trials" / "incremental");
    for (int seed = 1; seed <= seeds(); ++seed) {
      // Killed once the search is under way: after a random number of finished trials, or a
      // random number of rows into the incremental run (past its first checkpoint).
      std::mt19937 generator(static_cast<unsigned>(seed));
      const int finished = std::uniform_int_distribution<int>(1, trials - 2)(generator);
      const Index row = mode == "trials" ? 0
                                         : std::uniform_int_distribution<Index>(
                                               3, std::max<Index>(3, rows * 9 / 10))(generator);
      SCOPED_TRACE("seed " + std::to_string(seed));
      const fs::path dir = work() / (mode + "_killed_" + std::to_string(seed));
      Child child(arguments("fos", case_file, sets, {"--out", dir.string()}), work(), root_);
      const auto under_way = [&] {
        if (mode == "trials") {
          const std::string log = read_file(dir / "fos.log"); // a header, then a line per trial
          return std::count(log.begin(), log.end(), '\n') >= finished + 1;
        }
        return rows_written(dir / "trials" / "incremental") >= row;
      };
      while (!under_way()) {
        if (const auto done = child.poll())
          FAIL() << "the search ended before the kill:\n" << done->describe();
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
      }
      ::kill(child.pid(), SIGKILL);
      child.wait();
      const auto kept = finished_trial_files(dir);
      if (mode == "trials") {
        ASSERT_GE(kept.size(), static_cast<std::size_t>(finished));
      }
      const Outcome r = resume("fos", case_file, sets, dir);
      ASSERT_EQ(r.exit_code, 0) << r.describe();
      for (const auto& [file, written] : kept) // kept, not run again
        EXPECT_EQ(fs::last_write_time(file), written) << file;
      EXPECT_EQ(fos_rows(reference), fos_rows(dir));
      const auto a = read_json(reference / "fos.json");
      const auto b = read_json(dir / "fos.json");
      EXPECT_EQ(a.at("bracket"), b.at("bracket"));
      EXPECT_EQ(a.at("newton_iterations"), b.at("newton_iterations"));
    }
  }
}

// The newest checkpoint truncated (a kill while the disk was writing it, were the write not
// atomic) or with a flipped byte: it is skipped with a message naming it, the one before is
// used, and the run still ends where the uninterrupted one did.
TEST_F(Restart, ADamagedCheckpointIsSkippedForThePreviousOne) {
  const fs::path case_file = kCases / "colliding_discs.yaml";
  const std::vector<std::string> sets = {"grid.cell_size=0.0125",
                                         "output.checkpoint.every_steps=25"};
  const fs::path reference = work() / "reference";
  run_to_end(case_file, sets, reference);
  for (const std::string damage : {"truncated", "flipped"}) {
    SCOPED_TRACE(damage);
    const fs::path dir = work() / damage;
    run_and_kill(case_file, sets, dir, 200);
    const auto checkpoints = talus::list_checkpoints(dir / "checkpoints");
    ASSERT_EQ(checkpoints.size(), 2u);
    const fs::path newest = checkpoints.front();
    std::string bytes = read_file(newest);
    if (damage == "truncated")
      bytes.resize(bytes.size() / 2);
    else
      bytes[bytes.size() / 2] = static_cast<char>(bytes[bytes.size() / 2] ^ 0x10);
    write_file(newest, bytes);
    const Outcome r = resume("run", case_file, sets, dir);
    ASSERT_EQ(r.exit_code, 0) << r.describe();
    EXPECT_NE(r.err.find("skipped checkpoint '" + newest.string() + "'"), std::string::npos)
        << r.describe();
    EXPECT_NE(r.err.find(damage == "truncated" ? "truncated" : "checksum"), std::string::npos)
        << r.describe();
    EXPECT_NE(r.err.find("resuming from '" + checkpoints.back().string() + "'"), std::string::npos)
        << r.describe();
    expect_same_series(reference, dir, {});
    expect_same_frames(reference, dir, {});
  }
}

// Resuming with a case that differs: refused by key, nothing written; the keys that may change
// (end time, output) only with --accept-changes.
TEST_F(Restart, AChangedCaseIsRefusedByKey) {
  const fs::path case_file = kCases / "colliding_discs.yaml";
  const std::vector<std::string> sets = {"grid.cell_size=0.0125",
                                         "output.checkpoint.every_steps=25"};
  const fs::path dir = work() / "killed";
  run_and_kill(case_file, sets, dir, 200);
  const std::string series = read_file(dir / "timeseries.csv");
  auto changed = sets;
  changed.push_back("materials[0].youngs_modulus=2e5");
  Outcome r = resume("run", case_file, changed, dir, {"--accept-changes"});
  EXPECT_EQ(r.exit_code, 2) << r.describe();
  EXPECT_NE(r.err.find("materials[0].youngs_modulus"), std::string::npos) << r.describe();
  EXPECT_TRUE(read_file(dir / "timeseries.csv") == series) << "a refused resume wrote";

  changed = sets;
  changed.push_back("time.end_time=0.06");
  r = resume("run", case_file, changed, dir);
  EXPECT_EQ(r.exit_code, 2) << r.describe();
  EXPECT_NE(r.err.find("time.end_time"), std::string::npos) << r.describe();
  EXPECT_NE(r.err.find("--accept-changes"), std::string::npos) << r.describe();

  r = resume("run", case_file, changed, dir, {"--accept-changes"});
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_DOUBLE_EQ(read_json(dir / "summary.json").at("final_time").get<double>(), 0.06);
}

// A disk that fills up: the checkpoint that no longer fits stops the run with the system's
// reason, leaves no temporary file, and the two before it stay whole; the run resumes from them
// once there is room. The disk is a small tmpfs (mounting needs root: CI runs as root).
TEST_F(Restart, AFullDiskStopsTheRunAndKeepsThePreviousCheckpoint) {
  if (::geteuid() != 0)
    GTEST_SKIP() << "mounting a small tmpfs needs root";
  // The beam writes a frame at its start and end only, so after the first frame only the
  // checkpoints (every second step) and a few hundred bytes of rows per step need room.
  const fs::path case_file = kCases / "cantilever_large.yaml";
  const std::vector<std::string> sets = {"output.every_steps=1000",
                                         "output.checkpoint.every_steps=2"};
  const fs::path reference = work() / "reference";
  run_to_end(case_file, sets, reference);
  const auto summary = read_json(reference / "summary.json");
  const auto checkpoint = summary.at("checkpoint_bytes").get<double>();
  const auto others = static_cast<double>(fs::file_size(reference / "run.h5")) +
                      static_cast<double>(fs::file_size(reference / "timeseries.csv")) +
                      static_cast<double>(fs::file_size(reference / "newton.log"));
  // Room for two checkpoints and a third's start: the third write fails.
  const auto size = static_cast<long>(others + 2.4 * checkpoint);
  const fs::path disk = root_ / "disk";
  fs::create_directory(disk);
  const std::string options = "size=" + std::to_string(size);
  ASSERT_EQ(::mount("tmpfs", disk.c_str(), "tmpfs", 0, options.c_str()), 0) << std::strerror(errno);
  struct Unmount {
    fs::path at;
    ~Unmount() { ::umount(at.c_str()); }
  } unmount{disk};
  const fs::path dir = disk / "run";
  const Outcome r = talus(arguments("run", case_file, sets, {"--out", dir.string()}));
  EXPECT_EQ(r.exit_code, 1) << r.describe();
  EXPECT_NE(r.err.find("cannot write checkpoint"), std::string::npos) << r.describe();
  EXPECT_NE(r.err.find("No space left on device"), std::string::npos) << r.describe();
  const auto kept = talus::list_checkpoints(dir / "checkpoints");
  EXPECT_EQ(kept.size(), 2u);
  for (const auto& file : kept) {
    std::string why;
    EXPECT_TRUE(talus::CheckpointReader::open(file, why).has_value()) << file << ": " << why;
  }
  for (const auto& entry : fs::directory_iterator(dir / "checkpoints"))
    EXPECT_NE(entry.path().extension(), ".tmp") << entry.path();
  EXPECT_GE(talus::ResultsReader(dir / "run.h5").frame_count(), 1);
  // With room again (a copy on the ordinary disk) the run resumes and ends as the reference.
  const fs::path moved = work() / "moved";
  fs::copy(dir, moved, fs::copy_options::recursive);
  const Outcome again = resume("run", case_file, sets, moved);
  ASSERT_EQ(again.exit_code, 0) << again.describe();
  expect_same_series(reference, moved, {1e-9});
  expect_same_frames(reference, moved, {1e-9});
}

} // namespace
