// `talus render` end to end: a short run of the talk's colliding discs with voxels, then the
// real binary draws it. Good requests write PNG files, checked by their signature and by what
// they show (tests/python/check_png.py: the checker's two colours in equal shares, a field's
// colour map, points drawn, frames that differ as the discs move); bad ones (a missing file, field,
// frame, component, or voxels that were never written) exit with 2, a message naming the option,
// and no picture.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

namespace {

namespace fs = std::filesystem;

struct Outcome {
  int exit_code;
  std::string stderr_text;
};

class Render : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("talus_render_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    const fs::path discs = fs::path(TALUS_TESTS_DIR).parent_path() / "cases/colliding_discs.yaml";
    // Three frames: t = 0, 0.0025, 0.005.
    const std::string common =
        " --set time.end_time=0.005 --set output.every_time=0.0025 > /dev/null 2>&1";
    ASSERT_EQ(talus("run '" + discs.string() + "' --out '" + (dir_ / "voxels").string() +
                    "' --set output.voxels=true" + common)
                  .exit_code,
              0);
    ASSERT_EQ(
        talus("run '" + discs.string() + "' --out '" + (dir_ / "plain").string() + "'" + common)
            .exit_code,
        0);
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }

  static Outcome talus(const std::string& args) {
    const fs::path err = dir_ / "stderr.txt";
    const std::string command = std::string(TALUS_BINARY) + " " + args + " 2> '" + err.string() +
                                "'" + (args.find('>') == std::string::npos ? " > /dev/null" : "");
    const int status = std::system(command.c_str());
    std::stringstream text;
    text << std::ifstream(err).rdbuf();
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, text.str()};
  }
  static std::string h5(const char* run) { return "'" + (dir_ / run / "run.h5").string() + "'"; }
  static bool is_png(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    char signature[8] = {};
    in.read(signature, 8);
    return in && std::string(signature, 8) == "\x89PNG\r\n\x1a\n";
  }
  /// tests/python/check_png.py MODE FILES... passes (the picture shows what it should).
  static bool picture_holds(const std::string& mode, const std::vector<fs::path>& files) {
    std::string command =
        "/usr/bin/python3 '" + std::string(TALUS_TESTS_DIR) + "/python/check_png.py' " + mode;
    for (const auto& f : files)
      command += " '" + f.string() + "'";
    return std::system(command.c_str()) == 0;
  }
  static fs::path dir_;
};
fs::path Render::dir_;

TEST_F(Render, DrawsVoxelsByFieldAndByPattern) {
  const fs::path field = dir_ / "stress_xy.png", pattern = dir_ / "checker.png";
  EXPECT_EQ(
      talus("render " + h5("voxels") + " --field stress --component xy -o '" + field.string() + "'")
          .exit_code,
      0);
  EXPECT_TRUE(is_png(field));
  EXPECT_TRUE(picture_holds("field", {field}));
  EXPECT_EQ(
      talus("render " + h5("voxels") + " --pattern checker --frame 1 -o '" + pattern.string() + "'")
          .exit_code,
      0);
  EXPECT_TRUE(is_png(pattern));
  EXPECT_TRUE(picture_holds("pattern", {pattern}));
}

TEST_F(Render, FrameAllWritesANumberedSequence) {
  const fs::path out = dir_ / "seq" / "v.png";
  ASSERT_EQ(talus("render " + h5("plain") + " --field velocity --mode points --frame all -o '" +
                  out.string() + "'")
                .exit_code,
            0);
  for (const char* name : {"v_000000.png", "v_000001.png", "v_000002.png"}) {
    EXPECT_TRUE(is_png(out.parent_path() / name)) << name;
    EXPECT_TRUE(picture_holds("drawn", {out.parent_path() / name})) << name;
  }
  // The discs move between the frames (0.025 m, a cell, at 5 m/s over 0.005 s).
  EXPECT_TRUE(picture_holds(
      "differ", {out.parent_path() / "v_000000.png", out.parent_path() / "v_000002.png"}));
  EXPECT_FALSE(fs::exists(out.parent_path() / "v_000003.png"));
}

TEST_F(Render, BadRequestsExitWithTwoNameTheOptionAndWriteNothing) {
  const fs::path out = dir_ / "bad.png";
  const struct {
    std::string args, message;
  } cases[] = {
      {"render " + h5("voxels") + " --field stres --component xy",
       "--field: field 'stres' is not in frame 2"},
      {"render " + h5("voxels") + " --field stress --component xy --frame 7",
       "--frame: frame 7 is not in the results (frames 0 to 2)"},
      {"render " + h5("voxels") + " --field stress --frame first", "--frame: expected a frame"},
      {"render " + h5("voxels") + " --field stress --component qq",
       "--component: field 'stress' has no component 'qq'"},
      {"render " + h5("voxels") + " --field stress", "choose one with --component"},
      {"render " + h5("plain") + " --pattern checker", "has no voxels"},
      {"render " + h5("voxels") + " --pattern dots", "--pattern: unknown pattern 'dots'"},
      {"render '" + (dir_ / "missing.h5").string() + "' --field stress",
       "missing.h5: no such results file"},
  };
  for (const auto& c : cases) {
    const Outcome o = talus(c.args + " -o '" + out.string() + "'");
    EXPECT_EQ(o.exit_code, 2) << c.args;
    EXPECT_NE(o.stderr_text.find(c.message), std::string::npos)
        << c.args << "\nstderr: " << o.stderr_text;
    EXPECT_FALSE(fs::exists(out)) << c.args;
  }
}

} // namespace
