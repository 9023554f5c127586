// `talus render` end to end: a short run of the talk's colliding discs with voxels, then the
// real binary draws it. Good requests write PNG files, checked by their signature and by what
// they show (tests/python/check_png.py: the checker's two colours in equal shares, a field's
// colour map, points drawn, frames that differ as the discs move); bad ones (a missing file, field,
// frame, component, or voxels that were never written) exit with 2, a message naming the option,
// and no picture. Render3D: a small 3D box with voxels, drawn as slices and as its outer faces;
// its geometry (polygons and areas of a slice, the count of outer faces) is checked by
// tests/python/check_render3d.py on the run's own voxels.
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

// The colour scale's options, each against what it must show: a range above every value draws
// the map's lowest colour only, the change of frame 0 from itself one colour, while the change
// of the last frame varies; a log scale and a crop draw a picture of their own.
TEST_F(Render, ColourRangeLogCropAndChange) {
  const auto draw = [&](const std::string& options, const char* name) {
    const fs::path out = dir_ / name;
    EXPECT_EQ(
        talus("render " + h5("voxels") + " " + options + " -o '" + out.string() + "'").exit_code, 0)
        << options;
    return out;
  };
  const fs::path plain = draw("--field stress --component xy", "plain.png");
  const fs::path above = draw("--field stress --component xy --clim 1e12 2e12", "above.png");
  EXPECT_TRUE(picture_holds("field", {plain}));
  EXPECT_TRUE(picture_holds("lowest", {above}));
  EXPECT_FALSE(picture_holds("lowest", {plain}));
  EXPECT_FALSE(picture_holds("one", {plain}));
  EXPECT_TRUE(picture_holds(
      "one", {draw("--field stress --component xy --delta --frame 0", "delta0.png")}));
  EXPECT_TRUE(picture_holds("field", {draw("--field stress --component xy --delta", "delta.png")}));
  const fs::path log = draw("--field velocity --log", "log.png");
  EXPECT_TRUE(picture_holds("drawn", {log}));
  const fs::path crop = draw("--field stress --component xy --crop 0 0 0.5 0.5", "crop.png");
  EXPECT_TRUE(picture_holds("field", {crop}));
  EXPECT_TRUE(picture_holds("differ", {plain, crop}));
  for (const char* bad :
       {"--field stress --component xy --clim 2 1",
        "--field stress --component xy --log --clim 0 1",
        "--field stress --component xy --crop 1 1 0 0", "--pattern checker --log"}) {
    const Outcome r =
        talus("render " + h5("voxels") + " " + bad + " -o '" + (dir_ / "bad.png").string() + "'");
    EXPECT_EQ(r.exit_code, 2) << bad << "\n" << r.stderr_text;
    EXPECT_FALSE(fs::exists(dir_ / "bad.png")) << bad;
  }
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

TEST_F(Render, SliceAndViewNeedA3DRun) {
  const fs::path out = dir_ / "bad.png";
  for (const char* option : {"--slice z=0.5", "--view iso"}) {
    const Outcome o =
        talus("render " + h5("voxels") + " --field mass " + option + " -o '" + out.string() + "'");
    EXPECT_EQ(o.exit_code, 2) << option;
    const std::string name = std::string(option).substr(0, std::string(option).find(' '));
    EXPECT_NE(o.stderr_text.find(name + ": "), std::string::npos) << o.stderr_text;
    EXPECT_NE(o.stderr_text.find("is a 2D result"), std::string::npos) << o.stderr_text;
    EXPECT_FALSE(fs::exists(out)) << option;
  }
}

// An axisymmetric run names its components by r, z and the hoop direction t: --component tt
// draws the hoop stress, and the plane-strain names are refused with the axisymmetric ones.
TEST_F(Render, AnAxisymmetricRunHasComponentsRZT) {
  const fs::path cylinder =
      fs::path(TALUS_TESTS_DIR).parent_path() / "verification/axisymmetric_cylinder.yaml";
  ASSERT_EQ(talus("run '" + cylinder.string() + "' --out '" + (dir_ / "axi").string() +
                  "' > /dev/null 2>&1")
                .exit_code,
            0);
  const fs::path hoop = dir_ / "hoop.png", bad = dir_ / "bad_axi.png";
  EXPECT_EQ(talus("render " + h5("axi") + " --field stress --component tt --mode points -o '" +
                  hoop.string() + "'")
                .exit_code,
            0);
  EXPECT_TRUE(is_png(hoop));
  const Outcome o =
      talus("render " + h5("axi") + " --field stress --component xx -o '" + bad.string() + "'");
  EXPECT_EQ(o.exit_code, 2);
  EXPECT_NE(o.stderr_text.find("allowed: rr, rz, rt, zz, zt, tt"), std::string::npos)
      << o.stderr_text;
  EXPECT_FALSE(fs::exists(bad));
}

// A box of 12 x 8 x 6 points (spacing 0.05 m) sheared for 0.02 s: three frames.
const char* const kBox3d = R"yaml(name: render_box_3d
dimension: 3
grid: {origin: [0, 0, 0], extent: [0.8, 0.6, 0.5], cell_size: 0.1}
materials:
  - {name: soft, model: neo_hookean, density: 20, youngs_modulus: 1.0e5, poisson_ratio: 0.3}
bodies:
  - {name: box, material: soft, shape: box, min: [0.1, 0.1, 0.1], max: [0.7, 0.5, 0.4],
     particles_per_cell: 2, velocity: ["0.5 * (y - 0.3)", 0, "0.3 * (x - 0.4)"]}
time: {end_time: 0.02, cfl: 0.5}
output: {every_time: 0.01, voxels: true}
solver: {shape: gimp, scheme: musl, flip: 1}
)yaml";

class Render3D : public Render {
protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("talus_render3d_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    std::ofstream(dir_ / "box.yaml") << kBox3d;
    ASSERT_EQ(talus("run '" + (dir_ / "box.yaml").string() + "' --out '" + (dir_ / "box").string() +
                    "' > /dev/null 2>&1")
                  .exit_code,
              0);
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
};

TEST_F(Render3D, SlicesAndOuterFacesAreDrawn) {
  const struct {
    std::string options, file, check;
  } pictures[] = {
      {"--field stress --component xy --slice z=0.25", "slice_z.png", "field"},
      {"--field velocity --component magnitude --slice x=0.3", "slice_x.png", "field"},
      {"--field stress --component xy --mode points --slice y=0.3", "slice_points.png", "drawn"},
      {"--field stress --component xy --view iso", "faces_iso.png", "shaded"},
      // Without --slice or --view: the slice through the point that moved the most.
      {"--field stress --component xy", "changed.png", "field"},
      {"--field velocity --component z --view y", "faces_y.png", "shaded"},
      {"--pattern checker --view z", "checker_z.png", "shaded"},
  };
  for (const auto& p : pictures) {
    const fs::path out = dir_ / p.file;
    EXPECT_EQ(
        talus("render " + h5("box") + " " + p.options + " -o '" + out.string() + "'").exit_code, 0)
        << p.options;
    EXPECT_TRUE(is_png(out)) << p.options;
    EXPECT_TRUE(picture_holds(p.check, {out})) << p.options;
  }
}

TEST_F(Render3D, SliceAndFaceGeometryHoldOnTheRun) {
  const std::string command = "/usr/bin/python3 '" + std::string(TALUS_TESTS_DIR) +
                              "/python/check_render3d.py' " + h5("box") + " 12 8 6";
  EXPECT_EQ(std::system(command.c_str()), 0);
}

TEST_F(Render3D, BadSlicesAndViewsExitWithTwoNameTheOptionAndWriteNothing) {
  const fs::path out = dir_ / "bad.png";
  const std::string sxx = " --field stress --component xx ";
  const struct {
    std::string options, message;
  } cases[] = {
      {sxx + "--slice w=1",
       "--slice: expected AXIS=VALUE with AXIS x, y or z (e.g. z=0.5), got 'w=1'"},
      {sxx + "--slice z=abc", "--slice: expected a number after 'z=', got 'abc'"},
      {sxx + "--slice z0.5", "--slice: expected AXIS=VALUE"},
      {sxx + "--slice z=0.9",
       "--slice: the plane z = 0.9 is outside the voxels of frame 2 (z from"},
      {sxx + "--slice x=-1 --mode points",
       "--slice: the plane x = -1 is outside the points of frame 2 (x from"},
      {sxx + "--slice y=2 --frame all", "outside the voxels of every selected frame"},
      {sxx + "--view top", "--view: unknown view 'top' (allowed: iso, x, y, z)"},
      {sxx + "--view x --slice z=0.2", "--view: a slice is drawn in its plane"},
      {" --field velocity --component w",
       "--component: field 'velocity' has no component 'w' (allowed: x, y, z, magnitude)"},
  };
  for (const auto& c : cases) {
    const Outcome o = talus("render " + h5("box") + c.options + " -o '" + out.string() + "'");
    EXPECT_EQ(o.exit_code, 2) << c.options;
    EXPECT_NE(o.stderr_text.find(c.message), std::string::npos)
        << c.options << "\nstderr: " << o.stderr_text;
    EXPECT_FALSE(fs::exists(out)) << c.options;
  }
}

} // namespace
