// End-to-end tests of the `talus` executable's other paths: an interrupted run, the state
// guard, the explicit time step's limit, info and help, the shipped cases, verify's known
// failures and bench's refusals (the run's files and bad input: test_cli.cpp).
#include "cli_discs_case.hpp"
#include "cli_support.hpp"
#include "talus/io/csv.hpp"
#include "talus/io/results.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace fs = std::filesystem;
using namespace talus::test_support;
using talus::Index;
using talus::ResultsReader;

namespace {

TEST_F(Cli, CliInterruptKeepsFramesReadable) {
  // The discs start at rest, so nothing can collide or leave the grid: the run goes on until it
  // is interrupted (end_time = 100 s would take hours).
  write_file(work() / "case.yaml", kCase);
  const fs::path out = work() / "out";
  const fs::path h5 = out / "run.h5";
  Child child({"run", "case.yaml", "--out", "out", "--set", "time.end_time=100", "--set",
               "output.every_steps=20", "--set", "bodies.lower.velocity=[0, 0]", "--set",
               "bodies.upper.velocity=[0, 0]"},
              work(), root_);
  ASSERT_TRUE(child.started());

  // Wait until at least two frames can be read (the writer may hold the file at any moment).
  bool ready = false;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (!ready && std::chrono::steady_clock::now() < deadline) {
    if (const auto early = child.poll())
      FAIL() << "talus exited before it was interrupted\n" << early->describe();
    std::error_code ec;
    if (fs::exists(h5, ec)) {
      try {
        ready = ResultsReader(h5).frame_count() >= 2;
      } catch (const std::exception&) {
        // the writer holds the file or is half-way through creating it
      }
    }
    if (!ready)
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ASSERT_TRUE(ready) << "run.h5 never held 2 readable frames\n" << child.output_so_far();

  ASSERT_EQ(::kill(child.pid(), SIGINT), 0);
  const auto outcome = child.wait_at_most(std::chrono::seconds(60));
  ASSERT_TRUE(outcome.has_value()) << "talus did not stop after SIGINT\n" << child.output_so_far();
  EXPECT_EQ(outcome->exit_code, 1) << outcome->describe();
  EXPECT_NE(outcome->err.find("interrupted"), std::string::npos) << outcome->describe();

  nlohmann::json summary;
  ASSERT_NO_THROW(summary = read_json(out / "summary.json")) << read_file(out / "summary.json");
  EXPECT_EQ(summary.at("status").get<std::string>(), "interrupted");
  const double final_time = summary.at("final_time").get<double>();
  EXPECT_GT(final_time, 0.0);
  EXPECT_LT(final_time, 100.0);
  const auto particles = summary.at("particles").get<long long>();
  EXPECT_GT(particles, 0);

  ResultsReader reader(h5);
  const Index frames = reader.frame_count();
  ASSERT_GE(frames, 2);
  EXPECT_EQ(summary.at("frames").get<long long>(), frames);
  // The final frame is the state at which the run stopped.
  EXPECT_NEAR(reader.frame_time(frames - 1), final_time, 1e-12 * std::max(1.0, final_time));
  EXPECT_EQ(reader.frame_step(frames - 1), summary.at("steps").get<long long>());
  for (Index f = 0; f < frames; ++f) {
    SCOPED_TRACE("frame " + std::to_string(f));
    if (f > 0) {
      EXPECT_GT(reader.frame_time(f), reader.frame_time(f - 1));
    }
    Index rows = 0, cols = 0;
    std::vector<double> position;
    ASSERT_NO_THROW(position = reader.read(f, "position", &rows, &cols));
    EXPECT_EQ(rows, particles);
    EXPECT_EQ(cols, 2);
    EXPECT_EQ(position.size(), static_cast<std::size_t>(rows * cols));
    EXPECT_TRUE(
        std::all_of(position.begin(), position.end(), [](double v) { return std::isfinite(v); }));
  }

  const talus::CsvTable series = talus::read_csv(out / "timeseries.csv");
  ASSERT_GE(series.rows(), 2u);
  EXPECT_NEAR(series.column("time").back(), final_time, 1e-12 * std::max(1.0, final_time));
}

// USL with linear hats is the documented small-mass-node instability: at CFL 0.9 a node that a
// point barely touches gets a huge velocity whose gradient inverts the points around it within
// tens of steps. The state guard must stop the run (exit 3) naming det F, the particle, the step
// and the time, and every frame already written must be the finite state of its step.
TEST_F(Cli, CliStateGuardStopsAnInvertedPoint) {
  write_file(work() / "case.yaml", kCase);
  const Outcome r = talus({"run", "case.yaml", "--out", "out", "--set", "solver.scheme=usl",
                           "--set", "solver.shape=linear", "--set", "time.cfl=0.9"});
  ASSERT_EQ(r.exit_code, 3) << r.describe();
  for (const char* part : {"state guard: det F = ", "<= 0", "at particle ", "initial position",
                           "step ", "t = ", "the last good frame is frame "})
    EXPECT_NE(r.err.find(part), std::string::npos) << part << "\n" << r.describe();

  const fs::path out = work() / "out";
  nlohmann::json summary;
  ASSERT_NO_THROW(summary = read_json(out / "summary.json")) << read_file(out / "summary.json");
  EXPECT_EQ(summary.at("status").get<std::string>(), "numerical_failure");
  EXPECT_NE(summary.at("message").get<std::string>().find("det F"), std::string::npos);
  const auto steps = summary.at("steps").get<long long>();
  EXPECT_GT(steps, 0);

  ResultsReader reader(out / "run.h5");
  const Index frames = reader.frame_count();
  ASSERT_GE(frames, 2) << r.describe();
  EXPECT_EQ(summary.at("frames").get<long long>(), frames);
  // The failing step is not written: the last frame lies at or before the last completed step.
  EXPECT_LE(reader.frame_step(frames - 1), steps);
  for (Index f = 0; f < frames; ++f) {
    SCOPED_TRACE("frame " + std::to_string(f));
    for (const char* field : {"position", "velocity", "F", "stress"}) {
      Index rows = 0, cols = 0;
      std::vector<double> values;
      ASSERT_NO_THROW(values = reader.read(f, field, &rows, &cols)) << field;
      EXPECT_TRUE(std::all_of(values.begin(), values.end(), [](double v) {
        return std::isfinite(v);
      })) << field;
    }
  }
}

// A fixed explicit step above h / c_p is refused at input, at the key, with the limit. One just
// below h / c_p passes the reader but the discs' initial speed |v| = 7.1 m/s lifts the Courant
// number dt (c_p + |v|) / h above 1 (c_p = 82 m/s): the run stops before its first step, naming
// the particle, and leaves the initial state as its frame.
TEST_F(Cli, CliExplicitTimeStepAboveTheLimit) {
  write_file(work() / "case.yaml", kCase);
  {
    const Outcome r = talus({"run", "case.yaml", "--out", "refused", "--set", "time.dt=6e-4"});
    EXPECT_EQ(r.exit_code, 2) << r.describe();
    for (const char* part :
         {"key 'time.dt'", "above the stability limit h / c_p = 0.000304", "material 'disc'"})
      EXPECT_NE(r.err.find(part), std::string::npos) << part << "\n" << r.describe();
    EXPECT_FALSE(fs::exists(work() / "refused"));
  }
  const Outcome r = talus({"run", "case.yaml", "--out", "out", "--set", "time.dt=3e-4"});
  ASSERT_EQ(r.exit_code, 3) << r.describe();
  for (const char* part : {"step 1, t = 0:", "Courant number", "exceeds 1", "at particle "})
    EXPECT_NE(r.err.find(part), std::string::npos) << part << "\n" << r.describe();
  ResultsReader reader(work() / "out" / "run.h5");
  ASSERT_EQ(reader.frame_count(), 1);
  EXPECT_EQ(reader.frame_time(0), 0.0);
}

TEST_F(Cli, CliInfoAndHelp) {
  {
    SCOPED_TRACE("talus info");
    const Outcome r = talus({"info"});
    EXPECT_EQ(r.exit_code, 0) << r.describe();
    EXPECT_NE(r.out.find(std::string("talus ") + TALUS_VERSION), std::string::npos) << r.describe();
  }
  {
    SCOPED_TRACE("talus --help");
    const Outcome r = talus({"--help"});
    EXPECT_EQ(r.exit_code, 0) << r.describe();
    EXPECT_NE(r.out.find("run"), std::string::npos) << r.describe();
    EXPECT_NE(r.out.find("verify"), std::string::npos) << r.describe();
    EXPECT_NE(r.out.find("info"), std::string::npos) << r.describe();
  }
  {
    SCOPED_TRACE("talus run --help");
    const Outcome r = talus({"run", "--help"});
    EXPECT_EQ(r.exit_code, 0) << r.describe();
    for (const char* option : {"--out", "--set", "--force", "--threads"})
      EXPECT_NE(r.out.find(option), std::string::npos) << option << "\n" << r.describe();
  }
  {
    SCOPED_TRACE("talus verify --help");
    const Outcome r = talus({"verify", "--help"});
    EXPECT_EQ(r.exit_code, 0) << r.describe();
    EXPECT_NE(r.out.find("--tier"), std::string::npos) << r.describe();
  }
  {
    SCOPED_TRACE("talus without a sub-command");
    const Outcome r = talus({});
    EXPECT_EQ(r.exit_code, 2) << r.describe();
    EXPECT_FALSE(r.err.empty()) << r.describe();
  }
  {
    SCOPED_TRACE("talus with an unknown sub-command");
    const Outcome r = talus({"frobnicate"});
    EXPECT_EQ(r.exit_code, 2) << r.describe();
    EXPECT_FALSE(r.err.empty()) << r.describe();
  }
  // None of these wrote anything.
  EXPECT_TRUE(directory_listing(work()).empty());
}

TEST_F(Cli, CliShippedCaseRuns) {
  const fs::path shipped =
      fs::weakly_canonical(fs::path(TALUS_TESTS_DIR "/..") / "cases" / "colliding_discs.yaml");
  ASSERT_TRUE(fs::is_regular_file(shipped)) << shipped;
  const Outcome r =
      talus({"run", shipped.string(), "--out", "out", "--set", "time.end_time=0.005"});
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  const fs::path out = work() / "out";
  for (const char* name : kResultFiles)
    EXPECT_TRUE(fs::is_regular_file(out / name)) << name;
  const nlohmann::json summary = read_json(out / "summary.json");
  EXPECT_EQ(summary.at("status").get<std::string>(), "completed");
  EXPECT_NEAR(summary.at("final_time").get<double>(), 0.005, 1e-12);
  ResultsReader reader(out / "run.h5");
  EXPECT_GE(reader.frame_count(), 2);
  // run.h5 keeps the case file as written.
  EXPECT_EQ(reader.case_text(), read_file(shipped));
  // The discs are 0.45 m apart and close at 14 m/s: until t = 0.005 s they fly freely, so
  // every point has moved by exactly v0 t (bound: the worst rounding of the position sums, 36
  // steps of eps at |x| <= 1, 8e-15; measured 1.5e-15), kept its velocity (measured 4.4e-13 of
  // 5 m/s) and carries no stress but round-off (measured 1.2e-9 Pa against E = 1e5 Pa).
  const Index last = reader.frame_count() - 1;
  const double t = reader.frame_time(last);
  Index rows = 0, cols = 0;
  const auto x0 = reader.read(0, "position", &rows, &cols);
  const auto v0 = reader.read(0, "velocity", &rows, &cols);
  const auto x1 = reader.read(last, "position", &rows, &cols);
  const auto v1 = reader.read(last, "velocity", &rows, &cols);
  ASSERT_EQ(x0.size(), x1.size());
  double drift = 0, velocity_change = 0, stress = 0;
  for (std::size_t k = 0; k < x0.size(); ++k) {
    drift = std::max(drift, std::abs(x1[k] - x0[k] - v0[k] * t));
    velocity_change = std::max(velocity_change, std::abs(v1[k] - v0[k]));
  }
  for (double s : reader.read(last, "stress", &rows, &cols))
    stress = std::max(stress, std::abs(s));
  EXPECT_LE(drift, 1e-14);
  EXPECT_LE(velocity_change, 1e-12);
  EXPECT_LE(stress, 5e-9);
}

// A known failure is shown as KNOWN FAIL with its defect and does not fail `talus verify`
// (rigid_rotation's FLIP row: FLIP's projection of a spin strains the disc's edge).
TEST_F(Cli, VerifyShowsAKnownFailureWithoutFailing) {
  const Outcome r = talus({"verify", "--case", "rigid_rotation", "--out", "verify"});
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_NE(r.out.find("KNOWN FAIL"), std::string::npos) << r.describe();
  EXPECT_NE(r.out.find("1 known failure"), std::string::npos) << r.describe();
  const nlohmann::json report = read_json(work() / "verify" / "report.json");
  int known = 0;
  for (const auto& row : report) {
    if (row.at("result") == "KNOWN FAIL") {
      ++known;
      EXPECT_FALSE(row.at("passed").get<bool>());
      EXPECT_FALSE(row.at("known_defect").get<std::string>().empty());
      EXPECT_EQ(row.at("acceptance"), "within");
    } else if (row.at("result") != "report") {
      EXPECT_EQ(row.at("result"), "PASS") << row.dump();
    }
  }
  EXPECT_EQ(known, 1);
}

} // namespace

// `talus bench --vs` compares two binaries only where that is defined (newton_cost,
// explicit_throughput) and only
// with a binary that exists: anything else is refused with exit 2 before a run starts.
TEST_F(Cli, BenchRefusesAComparisonItCannotMake) {
  struct Refusal {
    std::vector<std::string> args;
    std::string message;
  };
  for (const Refusal& c :
       {Refusal{
            {"bench", "--case", "fos_cost", "--vs", TALUS_BINARY},
            "--vs: only --case newton_cost and explicit_throughput compare with another binary"},
        Refusal{{"bench", "--case", "newton_cost", "--vs", "no/such/talus"},
                "--vs: 'no/such/talus' is not a file"},
        Refusal{{"bench", "--case", "newton_cost", "--repeats", "2"},
                "at least 3 repeats are needed"}}) {
    const Outcome r = talus(c.args);
    EXPECT_EQ(r.exit_code, 2) << r.describe();
    EXPECT_NE(r.err.find(c.message), std::string::npos) << r.describe();
    EXPECT_TRUE(directory_listing(work()).empty()) << "something was written";
  }
}
