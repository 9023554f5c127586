// End-to-end tests of the `talus` executable: every test runs the real binary (TALUS_BINARY) in
// a child process, in a fresh temporary directory, and checks its exit code, its messages and the
// files it leaves behind (run.h5, run.xmf, timeseries.csv, summary.json).
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

// -------------------------------------------------------------------------------------------------

TEST_F(Cli, CliRunWritesAllResultFiles) {
  write_file(work() / "case.yaml", kCase);
  const Outcome r = talus({"run", "case.yaml", "--out", "out", "--set", "time.end_time=0.01"});
  ASSERT_EQ(r.exit_code, 0) << r.describe();

  const fs::path out = work() / "out";
  for (const char* name : kResultFiles) {
    EXPECT_TRUE(fs::is_regular_file(out / name)) << name << " missing\n" << r.describe();
    std::error_code ec;
    EXPECT_GT(fs::file_size(out / name, ec), 0u) << name << " is empty";
  }
  // With --out, nothing goes to the default results/<name>/.
  EXPECT_FALSE(fs::exists(work() / "results"));
  EXPECT_NE(r.out.find("completed"), std::string::npos) << r.describe();

  nlohmann::json summary;
  ASSERT_NO_THROW(summary = read_json(out / "summary.json")) << read_file(out / "summary.json");
  EXPECT_EQ(summary.at("status").get<std::string>(), "completed");
  EXPECT_GT(summary.at("steps").get<long long>(), 0);
  EXPECT_NEAR(summary.at("final_time").get<double>(), 0.01, 1e-12);

  ResultsReader reader(out / "run.h5");
  const Index frames = reader.frame_count();
  ASSERT_GE(frames, 2);
  EXPECT_EQ(summary.at("frames").get<long long>(), frames);
  EXPECT_EQ(reader.frame_time(0), 0.0);
  EXPECT_NEAR(reader.frame_time(frames - 1), 0.01, 1e-12);
  EXPECT_EQ(reader.frame_step(frames - 1), summary.at("steps").get<long long>());

  const talus::CsvTable series = talus::read_csv(out / "timeseries.csv");
  ASSERT_FALSE(series.names.empty());
  EXPECT_EQ(series.names.front(), "time");
  EXPECT_TRUE(contains(series.names, "time"));
  EXPECT_TRUE(contains(series.names, "kinetic_energy"));
  ASSERT_GE(series.rows(), 2u);
  EXPECT_EQ(series.column("time").front(), 0.0);
  EXPECT_NEAR(series.column("time").back(), 0.01, 1e-12);
  EXPECT_GT(series.column("kinetic_energy").front(), 0.0);

  EXPECT_NE(read_file(out / "run.xmf").find("run.h5"), std::string::npos);
}

struct BadInput {
  std::string label;
  std::optional<std::string> case_text; // written to case.yaml; none: no case file at all
  std::vector<std::string> args;        // after "run"
  std::vector<std::string> expected;    // substrings of stderr
};

TEST_F(Cli, CliBadInputClasses) {
  const std::vector<std::string> std_args{"case.yaml", "--out", "out"};
  const std::vector<BadInput> cases = {
      {"unknown key",
       edited("    youngs_modulus: 1.0e5", "    youngs_modulu: 1.0e5"),
       std_args,
       {"case.yaml:11:5: key 'materials[0].youngs_modulu': unknown key 'youngs_modulu'",
        "did you mean 'youngs_modulus'?"}},
      {"wrong type",
       edited("density: 20", "density: abc"),
       std_args,
       {"case.yaml:10:14: key 'materials[0].density': expected a number, got 'abc'"}},
      // A missing top-level section points at the top-level map, whose key path is empty.
      {"missing time section",
       edited("time:\n  end_time: 0.07\n  cfl: 0.5\n", ""),
       std_args,
       {"talus: error: case.yaml:1:1: missing required key 'time'"}},
      {"missing end_time",
       edited("  end_time: 0.07\n", ""),
       std_args,
       {"case.yaml:29:3: key 'time': missing required key 'end_time'"}},
      {"E <= 0",
       edited("youngs_modulus: 1.0e5", "youngs_modulus: 0"),
       std_args,
       {"case.yaml:11:21: key 'materials[0].youngs_modulus': must be > 0"}},
      {"nu = 0.5",
       edited("poisson_ratio: 0.3", "poisson_ratio: 0.5"),
       std_args,
       {"case.yaml:12:20: key 'materials[0].poisson_ratio':", "(got 0.5)"}},
      {"nu = -1",
       edited("poisson_ratio: 0.3", "poisson_ratio: -1"),
       std_args,
       {"case.yaml:12:20: key 'materials[0].poisson_ratio':", "(got -1)"}},
      {"density <= 0",
       edited("density: 20", "density: 0"),
       std_args,
       {"case.yaml:10:14: key 'materials[0].density': must be > 0"}},
      // The lower disc moved left so that it sticks out of the grid at x < 0.
      {"body outside the grid",
       edited("centre: [0.2, 0.2]", "centre: [0.1, 0.2]"),
       std_args,
       {"case.yaml:18:13: key 'bodies[0].radius': body 'lower' extends outside the grid"}},
      {"dt <= 0",
       edited("  cfl: 0.5", "  dt: 0"),
       std_args,
       {"case.yaml:30:7: key 'time.dt': must be > 0"}},
      {"cfl >= 1",
       edited("  cfl: 0.5", "  cfl: 1"),
       std_args,
       {"case.yaml:30:8: key 'time.cfl':", "(got 1)"}},
      {"YAML syntax error",
       edited("extent: [1, 1]", "extent: [1, 1]]"),
       std_args,
       {"case.yaml:5:17: YAML syntax error"}},
      {"bad --set value",
       kCase,
       {"case.yaml", "--out", "out", "--set", "materials.disc.youngs_modulus=-1"},
       {"--set: key 'materials[0].youngs_modulus': must be > 0",
        "(from --set materials.disc.youngs_modulus=-1)"}},
      {"unknown sub-command option",
       kCase,
       {"case.yaml", "--out", "out", "--bogus-option"},
       {"--bogus-option"}},
      {"missing case file",
       std::nullopt,
       {"missing.yaml", "--out", "out"},
       {"missing.yaml", "cannot open case file 'missing.yaml'"}},
  };

  for (std::size_t i = 0; i < cases.size(); ++i) {
    const BadInput& c = cases[i];
    SCOPED_TRACE("sub-case: " + c.label);
    const fs::path dir = work() / ("case" + std::to_string(i));
    ASSERT_TRUE(fs::create_directory(dir));
    if (c.case_text)
      write_file(dir / "case.yaml", *c.case_text);
    std::vector<std::string> args{"run"};
    args.insert(args.end(), c.args.begin(), c.args.end());

    const Outcome r = talus(args, dir);
    EXPECT_EQ(r.exit_code, 2) << r.describe();
    for (const auto& text : c.expected)
      EXPECT_NE(r.err.find(text), std::string::npos) << "stderr lacks \"" << text << "\"\n"
                                                     << r.describe();
    // Nothing was written: neither the output directory nor the default results/.
    EXPECT_FALSE(fs::exists(dir / "out")) << r.describe();
    EXPECT_FALSE(fs::exists(dir / "results")) << r.describe();
    const std::set<std::string> expected_listing =
        c.case_text ? std::set<std::string>{"case.yaml"} : std::set<std::string>{};
    EXPECT_EQ(directory_listing(dir), expected_listing);
  }
}

TEST_F(Cli, CliExistingResultsSurvive) {
  write_file(work() / "case.yaml", kCase);
  write_file(work() / "bad.yaml", edited("density: 20", "density: abc"));
  const fs::path out = work() / "out";

  const Outcome first = talus({"run", "case.yaml", "--out", "out", "--set", "time.end_time=0.01"});
  ASSERT_EQ(first.exit_code, 0) << first.describe();
  const Snapshot before = snapshot(out);
  ASSERT_GT(before.h5_size, 0u);
  ASSERT_FALSE(before.content.at("summary.json").empty());

  {
    SCOPED_TRACE("(a) same directory without --force");
    const Outcome r = talus({"run", "case.yaml", "--out", "out", "--set", "time.end_time=0.02"});
    EXPECT_EQ(r.exit_code, 2) << r.describe();
    EXPECT_NE(r.err.find("--force"), std::string::npos) << r.describe();
    EXPECT_NE(r.err.find("'out'"), std::string::npos) << r.describe();
    expect_unchanged(before, out);
  }
  {
    SCOPED_TRACE("(b) bad case file with --force");
    const Outcome r = talus({"run", "bad.yaml", "--out", "out", "--force"});
    EXPECT_EQ(r.exit_code, 2) << r.describe();
    EXPECT_NE(r.err.find("bad.yaml:10:14: key 'materials[0].density'"), std::string::npos)
        << r.describe();
    expect_unchanged(before, out);
  }
  {
    SCOPED_TRACE("(b) bad --set value with --force");
    const Outcome r = talus({"run", "case.yaml", "--out", "out", "--force", "--set",
                             "materials.disc.poisson_ratio=0.5"});
    EXPECT_EQ(r.exit_code, 2) << r.describe();
    EXPECT_NE(r.err.find("--set: key 'materials[0].poisson_ratio'"), std::string::npos)
        << r.describe();
    expect_unchanged(before, out);
  }
  {
    SCOPED_TRACE("(c) valid case with --force");
    // A file that is not a result file; --force replaces only the run's own files.
    write_file(out / "notes.txt", "my notes\n");
    const Outcome r =
        talus({"run", "case.yaml", "--out", "out", "--force", "--set", "time.end_time=0.02"});
    ASSERT_EQ(r.exit_code, 0) << r.describe();
    for (const char* name : kResultFiles)
      EXPECT_TRUE(fs::is_regular_file(out / name)) << name;
    const std::string summary_text = read_file(out / "summary.json");
    EXPECT_NE(summary_text, before.content.at("summary.json"));
    const nlohmann::json summary = nlohmann::json::parse(summary_text);
    EXPECT_EQ(summary.at("status").get<std::string>(), "completed");
    EXPECT_NEAR(summary.at("final_time").get<double>(), 0.02, 1e-12);
    ResultsReader reader(out / "run.h5");
    ASSERT_GE(reader.frame_count(), 2);
    EXPECT_NEAR(reader.frame_time(reader.frame_count() - 1), 0.02, 1e-12);
    EXPECT_EQ(read_file(out / "notes.txt"), "my notes\n");
  }
}

} // namespace
