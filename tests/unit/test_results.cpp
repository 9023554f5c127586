// Results files: run.h5 round trip, field selection, frame-by-frame readability, run.xmf through
// real XDMF readers (tests/python/check_results.py), timeseries.csv and summary.json.
#include "talus/io/results.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

namespace fs = std::filesystem;
using namespace talus;

namespace {

const std::vector<OutputField> kAllFields{OutputField::Velocity, OutputField::Mass,
                                          OutputField::Volume,   OutputField::DeformationGradient,
                                          OutputField::Stress,   OutputField::Material};

/// A fresh, empty directory per test, removed afterwards.
class TempDir {
public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = fs::temp_directory_path() /
            ("talus_results_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  const fs::path& path() const { return path_; }

private:
  fs::path path_;
};

/// Distinct, non-round values everywhere so that a swapped component or row shows up.
Particles<2> make_particles(Index n, int frame) {
  Particles<2> p;
  p.resize(n);
  const double f = frame;
  for (Index i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const double d = static_cast<double>(i) + 0.1 * f;
    p.x[k] = Vec2(d / 3.0 + std::numbers::pi, -d / 7.0 + 1e-3 * std::numbers::e);
    p.v[k] = Vec2(std::sqrt(2.0) * (d + 1), -1.0 / (d + 3));
    p.mass[k] = 2.5e-3 * (d + 1) / 9.0;
    p.volume0[k] = 1e-6 * (d + 2) / 11.0;
    p.volume[k] = p.volume0[k] * (1 + 1e-3 * d);
    Mat2 f;
    f << 1 + 1e-3 * d, 2e-4 * (d + 1) / 3.0, -3e-4 * (d + 1) / 7.0, 1 - 1e-3 * d / 13.0;
    p.F[k] = embedded<2>(f);
    Mat3 s;
    const double a = -1e5 * (d + 1) / 3.0;
    s << a, 1.1e4 + d / 17.0, 2.3e3 - d,                        //
        1.1e4 + d / 17.0, 0.5 * a - 7, -4.7e2 * (d + 1) / 19.0, //
        2.3e3 - d, -4.7e2 * (d + 1) / 19.0, 0.3 * a + 1 / 23.0;
    p.stress[k] = s;
    p.material[k] = static_cast<int>(i % 3);
    p.body[k] = static_cast<int>((i * 7 + frame) % 5) - 1;
  }
  return p;
}

RunMetadata make_metadata() {
  RunMetadata m;
  m.case_name = "column_collapse";
  m.case_file = "cases/column collapse.yaml";
  m.case_text = "name: column_collapse\n# naïve comment, µm & <xml>\ngrid:\n  cell_size: 0.05\n";
  m.overrides = {"grid.cell_size=0.05", "time.end_time=1.5"};
  m.version = "0.1.0-test";
  m.dimension = 2;
  m.grid_origin = Vec3(0, -0.5, 0);
  m.grid_extent = Vec3(2, 1.25, 0);
  m.cell_size = 0.05;
  m.material_names = {"sand", "clay"};
  m.body_names = {"column", "floor", "block"};
  return m;
}

void expect_matrix(const ResultsReader& r, Index frame, const std::string& field,
                   const std::vector<double>& want, Index want_rows, Index want_cols) {
  Index rows = -1, cols = -1;
  const auto got = r.read(frame, field, &rows, &cols);
  EXPECT_EQ(rows, want_rows) << field;
  EXPECT_EQ(cols, want_cols) << field;
  ASSERT_EQ(got.size(), want.size()) << field;
  for (std::size_t i = 0; i < want.size(); ++i)
    EXPECT_EQ(got[i], want[i]) << field << "[" << i << "] frame " << frame; // bit-exact
}

void expect_frame_matches(const ResultsReader& r, Index frame, const Particles<2>& p) {
  const Index n = p.size();
  std::vector<double> x, v, F, s, mass(p.mass.begin(), p.mass.end()),
      vol(p.volume.begin(), p.volume.end()), mat(p.material.begin(), p.material.end()),
      body(p.body.begin(), p.body.end());
  for (Index i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    x.insert(x.end(), {p.x[k][0], p.x[k][1]});
    v.insert(v.end(), {p.v[k][0], p.v[k][1]});
    const Mat3& f = p.F[k];
    F.insert(F.end(),
             {f(0, 0), f(0, 1), f(0, 2), f(1, 0), f(1, 1), f(1, 2), f(2, 0), f(2, 1), f(2, 2)});
    const Mat3& t = p.stress[k];
    s.insert(s.end(), {t(0, 0), t(0, 1), t(0, 2), t(1, 1), t(1, 2), t(2, 2)});
  }
  expect_matrix(r, frame, "position", x, n, 2);
  expect_matrix(r, frame, "velocity", v, n, 2);
  expect_matrix(r, frame, "mass", mass, n, 1);
  expect_matrix(r, frame, "volume", vol, n, 1);
  expect_matrix(r, frame, "F", F, n, 9);
  expect_matrix(r, frame, "stress", s, n, 6);
  expect_matrix(r, frame, "material", mat, n, 1);
  expect_matrix(r, frame, "body", body, n, 1);
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

template <class F> std::string error_of(F&& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "<no exception>";
}

const double kTimes[3] = {0.0, 1.0 / 3.0 * 1e-3, 2.0 / 3.0 * 1e-3 + 1e-19};
const Index kSteps[3] = {0, 41, 9000000001LL};

} // namespace

TEST(Results, RoundTripAllFieldsBitExact) {
  TempDir dir;
  const fs::path out = dir.path() / "nested" / "run dir"; // created by the writer
  const Index n = 7;
  std::vector<Particles<2>> frames;
  {
    ResultsWriter w(out, make_metadata());
    EXPECT_EQ(w.h5_path(), out / "run.h5");
    for (int k = 0; k < 3; ++k) {
      frames.push_back(make_particles(n, k));
      w.write_frame(kSteps[k], kTimes[k], frames.back(), kAllFields);
      EXPECT_EQ(w.frames_written(), k + 1);
    }
  }
  EXPECT_TRUE(fs::exists(out / "run.xmf"));
  EXPECT_FALSE(fs::exists(out / "run.xmf.tmp"));

  ResultsReader r(out / "run.h5");
  ASSERT_EQ(r.frame_count(), 3);
  const std::vector<std::string> all{"position", "velocity", "mass",     "volume",
                                     "F",        "stress",   "material", "body"};
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(r.frame_time(k), kTimes[k]);
    EXPECT_EQ(r.frame_step(k), kSteps[k]);
    EXPECT_EQ(r.frame_fields(k), all);
    expect_frame_matches(r, k, frames[static_cast<std::size_t>(k)]);
  }
  const RunMetadata m = make_metadata();
  EXPECT_EQ(r.case_text(), m.case_text);
  EXPECT_EQ(r.metadata_string("case_name"), m.case_name);
  EXPECT_EQ(r.metadata_string("case_file"), m.case_file);
  EXPECT_EQ(r.metadata_string("version"), m.version);
  EXPECT_EQ(r.metadata_string("material_names"), "sand\nclay");
  EXPECT_EQ(r.metadata_string("body_names"), "column\nfloor\nblock");
  EXPECT_EQ(r.metadata_string("overrides"), "grid.cell_size=0.05\ntime.end_time=1.5");
  EXPECT_EQ(r.metadata_string("dimension"), "2");
  EXPECT_EQ(r.metadata_string("grid_origin"), "0 -0.5");
  EXPECT_EQ(r.metadata_string("grid_extent"), "2 1.25");
  EXPECT_EQ(std::stod(r.metadata_string("cell_size")), 0.05);

  // The sidecar references run.h5 relatively and describes every frame.
  const std::string xmf = slurp(out / "run.xmf");
  EXPECT_NE(xmf.find("run.h5:/frames/000002/position"), std::string::npos);
  EXPECT_EQ(xmf.find(out.string()), std::string::npos) << "absolute path in run.xmf";
  EXPECT_NE(xmf.find("AttributeType=\"Tensor6\""), std::string::npos);
}

TEST(Results, OnlyRequestedFieldsAreWritten) {
  TempDir dir;
  const auto p = make_particles(4, 0);
  {
    ResultsWriter w(dir.path(), make_metadata());
    w.write_frame(3, 0.5, p, {OutputField::Stress});
    w.write_frame(4, 0.75, p, {OutputField::Velocity, OutputField::Velocity}); // duplicate ok
  }
  ResultsReader r(dir.path() / "run.h5");
  ASSERT_EQ(r.frame_count(), 2);
  EXPECT_EQ(r.frame_fields(0), (std::vector<std::string>{"position", "stress"}));
  EXPECT_EQ(r.frame_fields(1), (std::vector<std::string>{"position", "velocity"}));
  const std::string msg = error_of([&] { r.read(0, "velocity", nullptr, nullptr); });
  EXPECT_NE(msg.find("velocity"), std::string::npos) << msg;
  EXPECT_NE(msg.find("frame 0"), std::string::npos) << msg;
  Index rows = 0, cols = 0;
  EXPECT_EQ(r.read(1, "velocity", &rows, &cols).size(), 8u);
  EXPECT_EQ(cols, 2);

  // Frame 0 of run.xmf has stress and no velocity; frame 1 the reverse.
  const std::string xmf = slurp(dir.path() / "run.xmf");
  const auto frame1 = xmf.find("frame_000001");
  ASSERT_NE(frame1, std::string::npos);
  EXPECT_EQ(xmf.substr(0, frame1).find("velocity"), std::string::npos);
  EXPECT_NE(xmf.substr(0, frame1).find("stress"), std::string::npos);
  EXPECT_NE(xmf.substr(frame1).find("velocity"), std::string::npos);
  EXPECT_EQ(xmf.substr(frame1).find("stress"), std::string::npos);
}

// plastic_strain is written from the frame's gathered values (the materials' history), as a
// scalar in run.h5 and in run.xmf; asking for it without values, or with the wrong count, is
// the caller's error.
TEST(Results, PlasticStrainIsWrittenFromTheFrameData) {
  TempDir dir;
  const auto p = make_particles(4, 0);
  const std::vector<double> kappa = {0.0, 1.25e-3, 3.0 / 7.0, 2.0e-6};
  {
    ResultsWriter w(dir.path(), make_metadata());
    FramePost<2> post;
    EXPECT_THROW(w.write_frame(0, 0, p, {OutputField::PlasticStrain}, post), std::invalid_argument);
    const std::vector<double> short_list(3, 0.0);
    post.plastic_strain = &short_list;
    EXPECT_THROW(w.write_frame(0, 0, p, {OutputField::PlasticStrain}, post), std::invalid_argument);
    post.plastic_strain = &kappa;
    w.write_frame(0, 0, p, {OutputField::Stress, OutputField::PlasticStrain}, post);
  }
  ResultsReader r(dir.path() / "run.h5");
  ASSERT_EQ(r.frame_count(), 1);
  EXPECT_EQ(r.frame_fields(0), (std::vector<std::string>{"position", "stress", "plastic_strain"}));
  Index rows = 0, cols = 0;
  EXPECT_EQ(r.read(0, "plastic_strain", &rows, &cols), kappa); // bit for bit
  EXPECT_EQ(rows, 4);
  EXPECT_EQ(cols, 1);
  const std::string xmf = slurp(dir.path() / "run.xmf");
  EXPECT_NE(xmf.find("<Attribute Name=\"plastic_strain\" AttributeType=\"Scalar\""),
            std::string::npos)
      << xmf;
  EXPECT_NE(xmf.find("run.h5:/frames/000000/plastic_strain"), std::string::npos);
}

TEST(Results, EveryFrameIsReadableWhileTheWriterIsAlive) {
  TempDir dir;
  ResultsWriter w(dir.path(), make_metadata());
  {
    ResultsReader r(w.h5_path()); // metadata only, no frame yet
    EXPECT_EQ(r.frame_count(), 0);
    EXPECT_EQ(r.metadata_string("case_name"), "column_collapse");
  }
  for (int k = 0; k < 3; ++k) {
    const auto p = make_particles(5, k);
    w.write_frame(kSteps[k], kTimes[k], p, kAllFields);
    // The writer closed run.h5 after the frame: another handle opens it and sees every frame.
    ResultsReader r(w.h5_path());
    ASSERT_EQ(r.frame_count(), k + 1);
    EXPECT_EQ(r.frame_time(k), kTimes[k]);
    expect_frame_matches(r, k, p);
    EXPECT_TRUE(fs::exists(dir.path() / "run.xmf"));
  }
}

// A resumed run (talus run --resume) keeps the frames its checkpoint lists and drops the rest,
// also when a kill left the file cut short in the middle of a later frame: the kept frames
// read back as written, and the writer goes on from there.
TEST(Results, AResumedWriterKeepsTheCheckpointsFramesOfADamagedFile) {
  for (const bool damaged : {false, true}) {
    SCOPED_TRACE(damaged ? "cut short" : "whole");
    TempDir dir;
    std::vector<ResultsWriter::FrameRecord> kept;
    std::uintmax_t size_at_checkpoint = 0;
    {
      ResultsWriter w(dir.path(), make_metadata());
      for (int k = 0; k < 3; ++k) {
        w.write_frame(kSteps[k], kTimes[k], make_particles(5, k), kAllFields);
        if (k == 1) {
          kept = w.frames();
          size_at_checkpoint = fs::file_size(w.h5_path());
        }
      }
    }
    const fs::path h5 = dir.path() / "run.h5";
    if (damaged) // killed half-way through the third frame
      fs::resize_file(h5, (size_at_checkpoint + fs::file_size(h5)) / 2);
    ResultsWriter resumed(dir.path(), make_metadata(), kept);
    {
      ResultsReader r(h5);
      ASSERT_EQ(r.frame_count(), 2);
      for (int k = 0; k < 2; ++k)
        expect_frame_matches(r, k, make_particles(5, k));
    }
    const auto p = make_particles(5, 2);
    resumed.write_frame(kSteps[2], kTimes[2], p, kAllFields);
    ResultsReader r(h5);
    ASSERT_EQ(r.frame_count(), 3);
    expect_frame_matches(r, 2, p);
  }
}

TEST(Results, WriterRejectsInconsistentParticleArrays) {
  TempDir dir;
  ResultsWriter w(dir.path(), make_metadata());
  auto p = make_particles(4, 0);
  p.stress.pop_back();
  EXPECT_THROW(w.write_frame(0, 0, p, {OutputField::Stress}), std::invalid_argument);
  EXPECT_EQ(w.frames_written(), 0);
  w.write_frame(0, 0, p, {OutputField::Velocity}); // stress not requested: fine
  EXPECT_EQ(ResultsReader(w.h5_path()).frame_count(), 1);
}

TEST(Results, ErrorsNameTheFileAndTheProblem) {
  TempDir dir;
  // Missing file.
  std::string msg = error_of([&] { ResultsReader r(dir.path() / "nope.h5"); });
  EXPECT_NE(msg.find("nope.h5"), std::string::npos) << msg;
  EXPECT_THROW(ResultsReader(dir.path() / "nope.h5"), std::runtime_error);
  // Not HDF5.
  std::ofstream(dir.path() / "junk.h5") << "not hdf5\n";
  msg = error_of([&] { ResultsReader r(dir.path() / "junk.h5"); });
  EXPECT_NE(msg.find("junk.h5"), std::string::npos) << msg;
  // run.h5 cannot be created (a directory is in the way): the HDF5 failure becomes an exception
  // naming the call and the path.
  fs::create_directories(dir.path() / "blocked" / "run.h5");
  msg = error_of([&] { ResultsWriter w(dir.path() / "blocked", make_metadata()); });
  EXPECT_NE(msg.find("H5Fcreate"), std::string::npos) << msg;
  EXPECT_NE(msg.find("blocked"), std::string::npos) << msg;
  // The results directory cannot be created (a file is in the way).
  std::ofstream(dir.path() / "file") << "x";
  EXPECT_THROW(ResultsWriter(dir.path() / "file" / "sub", make_metadata()), std::runtime_error);

  {
    ResultsWriter w(dir.path() / "ok", make_metadata());
    w.write_frame(0, 0, make_particles(2, 0), kAllFields);
  }
  ResultsReader r(dir.path() / "ok" / "run.h5");
  msg = error_of([&] { r.frame_time(1); });
  EXPECT_NE(msg.find("frame 1"), std::string::npos) << msg;
  EXPECT_THROW(r.read(-1, "position", nullptr, nullptr), std::runtime_error);
  EXPECT_THROW(r.read(0, "pressure", nullptr, nullptr), std::runtime_error);
  EXPECT_THROW(r.read(0, "", nullptr, nullptr), std::runtime_error);
  msg = error_of([&] { r.metadata_string("colour"); });
  EXPECT_NE(msg.find("colour"), std::string::npos) << msg;
}

TEST(Results, RerunReplacesTheOldRun) {
  TempDir dir;
  {
    ResultsWriter w(dir.path(), make_metadata());
    for (int k = 0; k < 3; ++k)
      w.write_frame(k, k, make_particles(3, k), kAllFields);
  }
  ResultsWriter w(dir.path(), make_metadata());
  EXPECT_FALSE(fs::exists(dir.path() / "run.xmf")) << "stale sidecar kept";
  w.write_frame(0, 0, make_particles(3, 0), kAllFields);
  EXPECT_EQ(ResultsReader(w.h5_path()).frame_count(), 1);
}

TEST(Results, XdmfOpensInVtkReaders) {
  TempDir dir;
  const Index n = 6;
  {
    ResultsWriter w(dir.path(), make_metadata());
    std::vector<OutputField> fields = kAllFields;
    fields.push_back(OutputField::PlasticStrain);
    for (int k = 0; k < 3; ++k) {
      std::vector<double> kappa(static_cast<std::size_t>(n));
      for (std::size_t i = 0; i < kappa.size(); ++i)
        kappa[i] = 1e-3 * static_cast<double>(i + 1) / (k + 3.0);
      FramePost<2> post;
      post.plastic_strain = &kappa;
      w.write_frame(kSteps[k], kTimes[k], make_particles(n, k), fields, post);
    }
  }
  const fs::path script = fs::path(TALUS_TESTS_DIR) / "python" / "check_results.py";
  ASSERT_TRUE(fs::exists(script)) << script;
  const std::string cmd = "/usr/bin/python3 '" + script.string() + "' '" + dir.path().string() +
                          "' --particles " + std::to_string(n) +
                          " --frames 3 --fields velocity,F,stress,mass,volume,material,body," +
                          "plastic_strain";
  const int status = std::system(cmd.c_str());
  ASSERT_NE(status, -1);
  ASSERT_TRUE(WIFEXITED(status)) << cmd;
  EXPECT_EQ(WEXITSTATUS(status), 0) << "failed: " << cmd;
}

TEST(Results, TimeSeriesHeaderRowsAndFullPrecision) {
  TempDir dir;
  const fs::path file = dir.path() / "timeseries.csv";
  const std::vector<std::vector<double>> rows{
      {0.0, 0.1, -2.5}, {1.0 / 3.0, 1e-300, 6.02214076e23}, {2.0 / 3.0, -0.0, 123456789.123}};
  {
    TimeSeriesWriter ts(file, {"time", "kinetic_energy", "probe_tip.y"});
    for (const auto& row : rows)
      ts.append(row);
    EXPECT_THROW(ts.append({1.0, 2.0}), std::invalid_argument);
    EXPECT_THROW(ts.append({1.0, 2.0, 3.0, 4.0}), std::invalid_argument);
    // Flushed row by row: complete while the writer is still open.
    std::ifstream in(file);
    std::string line;
    std::getline(in, line);
    EXPECT_EQ(line, "time,kinetic_energy,probe_tip.y");
    for (const auto& row : rows) {
      ASSERT_TRUE(std::getline(in, line));
      std::stringstream ss(line);
      std::string cell;
      for (double want : row) {
        ASSERT_TRUE(std::getline(ss, cell, ','));
        const double got = std::strtod(cell.c_str(), nullptr);
        EXPECT_EQ(got, want) << cell;
        EXPECT_EQ(std::signbit(got), std::signbit(want)) << cell;
      }
    }
    EXPECT_FALSE(std::getline(in, line)) << "extra line: " << line;
  }
  EXPECT_NE(slurp(file).find("0.10000000000000001"), std::string::npos); // %.17g
  const std::string msg =
      error_of([&] { TimeSeriesWriter ts(dir.path() / "missing" / "ts.csv", {"t"}); });
  EXPECT_NE(msg.find("missing/ts.csv"), std::string::npos) << msg;
  EXPECT_THROW(TimeSeriesWriter(dir.path() / "missing" / "ts.csv", {"t"}), std::runtime_error);
}

TEST(Results, SummaryJsonParsesBack) {
  TempDir dir;
  const fs::path file = dir.path() / "summary.json";
  RunSummary s;
  s.case_name = "column_collapse";
  s.status = "numerical_failure";
  s.message = "particle 12 left the grid at t = 0.31 s \"quoted\"";
  s.steps = 123456;
  s.final_time = 0.31000000000000005;
  s.particles = 8000;
  s.frames = 17;
  s.wall_seconds = 12.75;
  s.extra = {{"p2g_seconds", 3.5}, {"max_speed", 1.0 / 3.0}};
  write_summary_json(file, s);
  EXPECT_FALSE(fs::exists(dir.path() / "summary.json.tmp"));
  const auto j = nlohmann::json::parse(slurp(file));
  EXPECT_EQ(j.at("case"), "column_collapse");
  EXPECT_EQ(j.at("status"), "numerical_failure");
  EXPECT_EQ(j.at("message"), s.message);
  EXPECT_EQ(j.at("steps").get<Index>(), 123456);
  EXPECT_EQ(j.at("final_time").get<double>(), s.final_time);
  EXPECT_EQ(j.at("particles").get<Index>(), 8000);
  EXPECT_EQ(j.at("frames").get<Index>(), 17);
  EXPECT_EQ(j.at("wall_seconds").get<double>(), 12.75);
  EXPECT_EQ(j.at("p2g_seconds").get<double>(), 3.5);
  EXPECT_EQ(j.at("max_speed").get<double>(), 1.0 / 3.0);
  EXPECT_EQ(j.size(), 10u);

  // Rewriting replaces the file; an extra entry may not shadow a standard one.
  s.status = "completed";
  s.extra.clear();
  write_summary_json(file, s);
  EXPECT_EQ(nlohmann::json::parse(slurp(file)).at("status"), "completed");
  s.extra = {{"steps", 1.0}};
  EXPECT_THROW(write_summary_json(file, s), std::invalid_argument);
}
