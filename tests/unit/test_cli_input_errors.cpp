// Bad input through the real `talus` binary (issue 16): each input gets exit code 2 in well
// under a second, with a message naming file:line:column and the key, and nothing is written
// (no output directory, no results/, nothing existing touched).
#include "talus/io/case_vocabulary.hpp"
#include "talus/linalg/linear_solver.hpp"

#include "cli_support.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace talus::test_support;

namespace {

// The expected `case.yaml:<line>:<column>` locations below refer to this text (line 1 is
// "name: ...").
const std::string kCase = R"(name: input_errors
analysis: explicit
grid:
  origin: [0, 0]
  extent: [1, 1]
  cell_size: 0.05
materials:
  - name: soil
    model: linear_elastic
    density: 1000
    youngs_modulus: 1.0e6
    poisson_ratio: 0.3
bodies:
  - name: block
    material: soil
    shape: rectangle
    min: [0.1, 0.1]
    max: [0.4, 0.4]
    particles_per_cell: 2
    velocity: [0, 0]
time:
  end_time: 0.01
  cfl: 0.5
probes:
  - name: corner
    point: [0.2, 0.2]
)";

/// kCase (or `text`) with the one occurrence of `from` replaced by `to`.
std::string edited(const std::string& from, const std::string& to, std::string text = kCase) {
  return replaced_once(from, to, std::move(text));
}

const std::string kSecondBody = R"(  - name: inclusion
    material: soil
    shape: disc
    centre: [0.3, 0.3]
    radius: 0.1
)";

struct BadInput {
  std::string label;
  std::string case_text;
  std::vector<std::string> set;      // --set values
  std::vector<std::string> expected; // substrings of stderr
};

class CliInputErrors : public Cli {
protected:
  /// Runs `talus run case.yaml --out out` (and `talus check`) on each input in a directory of its
  /// own and checks exit 2, the messages, the time and that nothing was written.
  void expect_refused(const std::vector<BadInput>& inputs) {
    for (std::size_t i = 0; i < inputs.size(); ++i) {
      const BadInput& c = inputs[i];
      SCOPED_TRACE("input: " + c.label);
      const fs::path dir = work() / ("input" + std::to_string(i));
      ASSERT_TRUE(fs::create_directory(dir));
      write_file(dir / "case.yaml", c.case_text);
      for (const char* command : {"run", "check"}) {
        SCOPED_TRACE(command);
        std::vector<std::string> args{command, "case.yaml"};
        if (std::string(command) == "run")
          args.insert(args.end(), {"--out", "out"});
        for (const auto& s : c.set)
          args.insert(args.end(), {"--set", s});
        const auto start = std::chrono::steady_clock::now();
        const Outcome r = talus(args, dir);
        const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        EXPECT_EQ(r.exit_code, 2) << r.describe();
        // The process's own CPU time, not the wall clock (the machine may be busy with other
        // tests): measured 0.1 s, 0.5 s for the 5 MB inputs (yaml-cpp scanning them). The bound
        // is 3 s, 6x that, so that a slower machine passes while the costs it guards (15 s
        // for the did-you-mean search of a 5 MB key, minutes before a memory refusal) fail;
        // and no hang in wall time.
        EXPECT_LT(r.cpu_seconds, 3.0) << r.describe();
        EXPECT_LT(seconds, 10.0) << r.describe();
        for (const auto& text : c.expected)
          EXPECT_NE(r.err.find(text), std::string::npos) << "stderr lacks \"" << text << "\"\n"
                                                         << r.describe();
        // One line of message, whatever the input held.
        EXPECT_LT(r.err.size(), 1500u) << r.describe();
        EXPECT_EQ(directory_listing(dir), std::set<std::string>{"case.yaml"}) << r.describe();
      }
    }
  }
};

TEST_F(CliInputErrors, AbsurdSizesAreRefusedByTheMemoryEstimate) {
  const std::string full_body =
      edited("max: [0.4, 0.4]", "max: [62.5, 62.5]", edited("min: [0.1, 0.1]", "min: [0, 0]"));
  expect_refused({
      {"1 m grid of 1e-8 m cells",
       edited("extent: [1, 1]\n  cell_size: 0.05", "extent: [1, 1]\n  cell_size: 1.0e-8"),
       {},
       {"case.yaml:6:14: key 'grid.cell_size': the memory estimate of the case is", "TB",
        "MemTotal of /proc/meminfo"}},
      {"1000 m grid of 1e-9 m cells: 1e24 nodes, more than node ids can number",
       edited("extent: [1, 1]\n  cell_size: 0.05", "extent: [1000, 1000]\n  cell_size: 1.0e-9"),
       {},
       {"case.yaml:6:14: key 'grid.cell_size': the grid has 1e+24 nodes (ghost layers included), "
        "more than Talus can number (4e+18)"}},
      {"4 m grid of 1e-7 m cells",
       edited("extent: [1, 1]\n  cell_size: 0.05", "extent: [4, 4]\n  cell_size: 1.0e-7"),
       {},
       {"case.yaml:6:14: key 'grid.cell_size': the memory estimate", "4e+07 x 4e+07 cells"}},
      {"1e15 cells per axis (no integer wrap-around)",
       edited("extent: [1, 1]\n  cell_size: 0.05", "extent: [1.0e15, 1.0e15]\n  cell_size: 1"),
       {},
       {"case.yaml:6:14: key 'grid.cell_size': the grid has 1e+30 nodes"}},
      {"a body of 1e10 points",
       edited("particles_per_cell: 2", "particles_per_cell: 16", full_body),
       {"grid.extent=[62.5, 62.5]", "grid.cell_size=0.01"},
       {"--set: key 'grid.cell_size': the memory estimate", "1e+10 material points"}},
      // With one point per direction the same body would fit: the key is its points per cell.
      {"a body of 2.3e9 points (16 per direction)",
       edited("particles_per_cell: 2", "particles_per_cell: 16", full_body),
       {"grid.extent=[62.5, 62.5]", "grid.cell_size=0.02083333333333333"},
       {"case.yaml:19:25: key 'bodies[0].particles_per_cell': the memory estimate"}},
      {"an extent of 1e308",
       edited("extent: [1, 1]", "extent: [1.0e308, 1.0e308]"),
       {},
       {"case.yaml:6:14: key 'grid.cell_size': the grid extent in x (1e+308 m) divided by the "
        "cell size (0.05 m) is inf cells, more than can be counted"}},
      {"origin + extent beyond the double range",
       edited("origin: [0, 0]\n  extent: [1, 1]", "origin: [1.0e308, 0]\n  extent: [1.0e308, 1]"),
       {},
       {"case.yaml:5:11: key 'grid.extent': origin + extent overflows"}},
  });
}

TEST_F(CliInputErrors, ExistingResultsSurviveAMemoryRefusal) {
  write_file(work() / "case.yaml", kCase);
  const Outcome first = talus({"run", "case.yaml", "--out", "out"});
  ASSERT_EQ(first.exit_code, 0) << first.describe();
  const Snapshot before = snapshot(work() / "out");
  const Outcome r =
      talus({"run", "case.yaml", "--out", "out", "--force", "--set", "grid.cell_size=1e-9"});
  EXPECT_EQ(r.exit_code, 2) << r.describe();
  EXPECT_NE(r.err.find("--set: key 'grid.cell_size': the memory estimate"), std::string::npos)
      << r.describe();
  expect_unchanged(before, work() / "out");
}

TEST_F(CliInputErrors, SilentlyAcceptedInputsAreRefused) {
  expect_refused({
      {"probe point outside the grid",
       edited("point: [0.2, 0.2]", "point: [2, 0.2]"),
       {},
       {"case.yaml:26:12: key 'probes[0].point': probe point [2, 0.2] lies outside the grid; "
        "the grid covers x in [0, 1], y in [0, 1]"}},
      {"point load outside the grid",
       kCase + "point_loads:\n  - {name: push, point: [0.2, -3], force: [0, -1]}\n",
       {},
       {"case.yaml:28:25: key 'point_loads[0].point': point load at [0.2, -3] lies outside the "
        "grid"}},
      {"overlapping bodies",
       edited("time:\n", kSecondBody + "time:\n"),
       {},
       {"case.yaml:21:5: key 'bodies[1]': body 'inclusion' overlaps body 'block'",
        "twice the mass"}},
      {"YAML tag !weird",
       edited("density: 1000", "density: !weird 1000"),
       {},
       {"case.yaml:10:14: key 'materials[0].density': YAML tags are not part of the case "
        "format (this value is tagged '!weird')"}},
      {"YAML tag !!binary",
       edited("name: corner", "name: !!binary Y29ybmVy"),
       {},
       {"case.yaml:25:11: key 'probes[0].name': YAML tags are not part of the case format",
        "tag:yaml.org,2002:binary"}},
      {"--set value with a second YAML document",
       kCase,
       {"time.cfl=0.4\n---\nfoo: 1"},
       {"--set: key 'time.cfl': the value holds more than one YAML document"}},
  });
}

TEST_F(CliInputErrors, NamesMustBePrintableUtf8) {
  expect_refused({
      {"case name not UTF-8",
       edited("name: input_errors", "name: input\xff\xfe_errors"),
       {},
       {"case.yaml:1:7: key 'name': the name 'input\\xff\\xfe_errors' is not valid UTF-8 (byte "
        "0xff at position 5)"}},
      {"body name with a tab",
       edited("name: block", "name: \"blo\\tck\""),
       {},
       {"case.yaml:14:11: key 'bodies[0].name': the name 'blo\\x09ck' holds a control "
        "character"}},
      {"material name not UTF-8 (overlong '/')",
       edited("  - name: soil", "  - name: \"so\xc0\xafil\"",
              edited("material: soil", "material: x")),
       {},
       {"case.yaml:8:11: key 'materials[0].name': the name 'so\\xc0\\xafil' is not valid "
        "UTF-8"}},
      {"probe name with a comma (a column of timeseries.csv)",
       edited("name: corner", "name: \"a,b\""),
       {},
       {"case.yaml:25:11: key 'probes[0].name': the name 'a,b' holds a comma"}},
  });
}

TEST_F(CliInputErrors, MessagesSayWhatIsReallyWrong) {
  std::string cr_only = kCase;
  for (char& c : cr_only)
    if (c == '\n')
      c = '\r';
  std::string deep = "[0, 0]";
  for (int i = 0; i < 80; ++i)
    deep = "[" + deep + "]";
  std::string very_deep = "0";
  for (int i = 0; i < 3000; ++i)
    very_deep = "[" + very_deep + "]";
  expect_refused({
      {"unterminated quote",
       edited("name: input_errors", "name: \"input_errors"),
       {},
       {"case.yaml:1:7: key 'name': unterminated quoted string: the \" opened here is never "
        "closed"}},
      {"unterminated single quote",
       edited("model: linear_elastic", "model: 'linear_elastic"),
       {},
       {"case.yaml:9:12: key 'materials[0].model': unterminated quoted string"}},
      {"CR-only line ends",
       cr_only,
       {},
       {"case.yaml:1:19: key 'name': the line ends here with a carriage return alone"}},
      {"nesting past the limit",
       edited("velocity: [0, 0]", "velocity: " + deep),
       {},
       {"case.yaml:20:", "key 'bodies[0].velocity[0][0]", "nest more than 64 levels"}},
      {"nesting past yaml-cpp's depth limit",
       edited("velocity: [0, 0]", "velocity: " + very_deep),
       {},
       {"case.yaml:20:", "key 'bodies[0].velocity'", "nest more than 400 levels deep here"}},
      {"self-intersecting polygon (a bow tie)",
       edited("shape: rectangle\n    min: [0.1, 0.1]\n    max: [0.4, 0.4]",
              "shape: polygon\n    vertices: [[0.1, 0.1], [0.4, 0.4], [0.4, 0.1], [0.1, 0.4]]"),
       {},
       {"case.yaml:17:15: key 'bodies[0].vertices': the polygon is not simple: edge 0-1 "
        "touches edge 2-3"}},
      {"collinear polygon",
       edited("shape: rectangle\n    min: [0.1, 0.1]\n    max: [0.4, 0.4]",
              "shape: polygon\n    vertices: [[0.1, 0.1], [0.2, 0.2], [0.3, 0.3], [0.4, 0.4]]"),
       {},
       {"case.yaml:17:15: key 'bodies[0].vertices': the polygon has zero area: its vertices "
        "lie on one line"}},
  });
}

TEST_F(CliInputErrors, PositionsAreThoseOfTheValue) {
  const std::string plastic =
      edited("    model: linear_elastic\n", "    model: mohr_coulomb\n    cohesion: 1.0e3\n"
                                            "    friction_angle: 30\n");
  // Lines of `plastic` below line 9 move down by 2.
  expect_refused({
      {"velocity expression that is NaN",
       edited("velocity: [0, 0]", "velocity: [\"sqrt(x - 1)\", 0]"),
       {},
       {"case.yaml:20:16: key 'bodies[0].velocity[0]': velocity expression 'sqrt(x - 1)' is "
        "not a number (NaN) at (0.1125, 0.1125)"}},
      {"probe particle index out of range",
       edited("point: [0.2, 0.2]", "particle: 100000"),
       {},
       {"case.yaml:26:15: key 'probes[0].particle': probe 'corner' names particle 100000, but "
        "the scene has 144 particles"}},
      {"uniform initial stress outside the yield surface",
       edited("    velocity: [0, 0]\n",
              "    velocity: [0, 0]\n    initial_stress: {type: uniform, stress: [1.0e6, 0, 0, "
              "0]}\n",
              plastic),
       {},
       {"case.yaml:23:45: key 'bodies[0].initial_stress.stress': material 'soil': the initial "
        "stress of point 0",
        "lies outside the Mohr-Coulomb yield surface"}},
  });
}

TEST_F(CliInputErrors, TheCostOfABadValueIsBounded) {
  const std::string huge(5 * 1000 * 1000, 'q');
  expect_refused({
      {"5 MB unknown value",
       kCase + "solver:\n  shape: " + huge + "\n",
       {},
       {"case.yaml:28:10: key 'solver.shape': unknown value 'qqqqqqqqqq",
        "qqq...' (allowed: "
        "gimp, linear, cpgimp, "
        "bspline2, bspline3, cpdi)"}},
      {"5 MB plain key (YAML's limit is 1024 characters)",
       kCase + huge + ": 1\n",
       {},
       {"case.yaml:27:1: this key, 'qqqq", "...', is 5000000 characters long; YAML allows at "
                                           "most 1024 for a key"}},
      {"5 MB explicit key (\"? key\")",
       kCase + "? " + huge + "\n: 1\n",
       {},
       {"case.yaml:27:3: key 'qqqq", "qqq...': unknown key 'qqqq", "(allowed keys here: name, "}},
      // One command-line argument holds at most 128 kB (MAX_ARG_STRLEN).
      {"100 kB --set value",
       kCase,
       {"solver.shape=" + huge.substr(0, 100000)},
       {"--set: key 'solver.shape': unknown value 'qqqq",
        "...' (allowed: gimp, linear, cpgimp, bspline2, bspline3, cpdi)"}},
      {"100 kB --set key",
       kCase,
       {huge.substr(0, 100000) + "=1"},
       {"--set: key 'qqqq", "qqq...': unknown key 'qqqq", "(from --set qqqq"}},
  });
}

// Inputs the fuzzer (tests/fuzz) found, each a regression test: yaml-cpp 0.7 loops forever,
// allocating, on a comma where a document's root should start or after a root that is a flow
// collection (found as a comment line of cases/slope_runout.yaml that gained a leading ',').
TEST_F(CliInputErrors, FuzzFindingsAreRefusedQuickly) {
  expect_refused({
      {"a comma before the first key",
       ",# a comment that lost its place\n" + kCase,
       {},
       {"case.yaml:1:1: a comma outside any [list] or {map}: it separates nothing here"}},
      {"a comma after a flow-map document",
       "{name: x}\n,\n",
       {},
       {"case.yaml:2:1: a comma outside any [list] or {map}"}},
      {"a line starting with a comma left of the root's indentation",
       "    name: x\n# a comment\n, grid\n",
       {},
       {"case.yaml:3:1: a comma outside any [list] or {map}"}},
      {"a comma after a document marker",
       kCase + "--- ,\n",
       {},
       {"case.yaml:27:5: a comma outside any [list] or {map}"}},
      {"a --set value that is a comma",
       kCase,
       {"time.cfl=,"},
       {"--set: key 'time.cfl': the value ',': a comma outside any [list] or {map}"}},
  });
}

TEST_F(CliInputErrors, InfoListsEveryWordTheReaderTakes) {
  const Outcome r = talus({"info"});
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  std::vector<std::string> words = talus::choice_names(talus::material_model_choices());
  for (const auto& list :
       {talus::choice_names(talus::analysis_choices()),
        talus::choice_names(talus::shape_function_choices()),
        talus::choice_names(talus::update_scheme_choices()),
        talus::choice_names(talus::transfer_scheme_choices()), talus::available_linear_solvers()})
    words.insert(words.end(), list.begin(), list.end());
  for (const std::string& word : words)
    EXPECT_NE(r.out.find(" " + word), std::string::npos) << word << "\n" << r.describe();
  for (const char* plastic : {"von_mises", "tresca", "mohr_coulomb", "drucker_prager"})
    EXPECT_NE(r.out.find(plastic), std::string::npos) << plastic << "\n" << r.describe();
}

TEST_F(CliInputErrors, CheckValidatesPrintsTheEstimateAndWritesNothing) {
  write_file(work() / "case.yaml", kCase);
  const Outcome r = talus({"check", "case.yaml", "--set", "grid.cell_size=0.025"});
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  for (const char* part : {"case.yaml: valid case 'input_errors'", "40 x 40 cells of 0.025 m",
                           "block: about 576 material points", "memory    about", "machine   "})
    EXPECT_NE(r.out.find(part), std::string::npos) << part << "\n" << r.describe();
  EXPECT_EQ(directory_listing(work()), std::set<std::string>{"case.yaml"});
}

// Every shipped case and every verification case is still accepted, with its memory estimate,
// and without a plausibility warning (a benchmark in non-dimensional units silences its own).
TEST_F(CliInputErrors, ShippedCasesPassCheck) {
  const fs::path repo = fs::weakly_canonical(fs::path(TALUS_TESTS_DIR) / "..");
  int checked = 0;
  for (const char* dir : {"cases", "verification"})
    for (const auto& entry : fs::directory_iterator(repo / dir)) {
      if (entry.path().extension() != ".yaml")
        continue;
      SCOPED_TRACE(entry.path().string());
      const Outcome r = talus({"check", entry.path().string()});
      EXPECT_EQ(r.exit_code, 0) << r.describe();
      EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.describe();
      ++checked;
    }
  EXPECT_GE(checked, 20);
  EXPECT_TRUE(directory_listing(work()).empty());
}

} // namespace
