#pragma once
// Results of one run in a directory: run.h5 (frames), run.xmf (ParaView), timeseries.csv and
// summary.json. Layout documented in docs/output-format.md.
#include "talus/core/particles.hpp"
#include "talus/post/stress_recovery.hpp"
#include "talus/post/voxels.hpp"
#include "talus/spec/case_spec.hpp"

#include <array>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace talus {

/// Run-wide facts stored once in run.h5 (/metadata) and used by the XDMF sidecar.
struct RunMetadata {
  std::string case_name;
  std::string case_file;
  std::string case_text; ///< the case file verbatim
  std::vector<std::string> overrides;
  std::string version;
  int dimension = 2;
  std::string geometry = "plane_strain"; ///< 2D: plane_strain or axisymmetric; 3D: "3d"
  Vec3 grid_origin{0, 0, 0};             ///< the first `dimension` components are written
  Vec3 grid_extent{0, 0, 0};
  double cell_size = 0;
  std::vector<std::string> material_names;
  std::vector<std::string> body_names;
};

/// Frame data gathered outside the particle arrays: post-processing results written when the
/// case asks for them (output.stress_recovery, output.voxels; a null pointer writes nothing of
/// that kind), and the plastic strain, which lives in the materials' history.
template <int Dim> struct FramePost {
  const RecoveredStress<Dim>* stress = nullptr; ///< -> stress_smoothed and the grid/ group
  const Voxels<Dim>* voxels = nullptr;          ///< -> the voxels/ group
  /// One value per particle; required when the fields list plastic_strain.
  const std::vector<double>* plastic_strain = nullptr;
};

/// Appends frames to run.h5 and keeps run.xmf in step. The file is opened and closed around
/// every frame (and run.xmf replaced atomically), so every complete frame stays readable if the
/// run is interrupted later.
class ResultsWriter {
public:
  /// What run.xmf says about one frame (kept in a checkpoint, so a resumed run can rewrite it).
  struct FrameRecord {
    Index step = 0;
    double time = 0;
    Index particles = 0;
    std::vector<OutputField> fields;
    bool recovered = false; ///< has stress_smoothed and grid/
    bool voxels = false;    ///< has voxels/
    /// The grid/ group's nodes (x, y, z) and first node: the box the material reaches.
    std::array<Index, 3> grid_nodes{1, 1, 1};
    Vec3 grid_origin{0, 0, 0};
  };

  /// Creates `dir`/run.h5 (replacing an existing one) and writes the metadata.
  ResultsWriter(std::filesystem::path dir, RunMetadata metadata);
  /// Continues `dir`/run.h5 of a resumed run: keeps the frames in `kept` (the first
  /// kept.size() frames of the file), deletes any written after them, rewrites run.xmf.
  /// Throws std::runtime_error if the file lacks one of the kept frames.
  ResultsWriter(std::filesystem::path dir, RunMetadata metadata, std::vector<FrameRecord> kept);
  /// The writer of a distributed run's other ranks: writes nothing, counts the frames rank 0
  /// writes (skip_frame), so messages that name a frame agree on every rank.
  struct CountOnly {};
  /// `frames`: the frames already written (a resumed run's).
  ResultsWriter(CountOnly, Index frames) : frames_(frames) {}
  void skip_frame() { ++frames_; }
  /// Dim must be the metadata's dimension.
  template <int Dim>
  void write_frame(Index step, double time, const Particles<Dim>& particles,
                   const std::vector<OutputField>& fields, const FramePost<Dim>& post = {});
  Index frames_written() const { return frames_; }
  const std::vector<FrameRecord>& frames() const { return frame_info_; }
  const std::filesystem::path& h5_path() const { return h5_path_; }

private:
  void write_xdmf() const;
  std::filesystem::path dir_, h5_path_, xmf_path_;
  RunMetadata metadata_;
  Index frames_ = 0;
  std::vector<FrameRecord> frame_info_;
};

/// Reads run.h5 back (tests, `talus render`, restart).
class ResultsReader {
public:
  explicit ResultsReader(const std::filesystem::path& h5_file);
  ~ResultsReader();
  ResultsReader(const ResultsReader&) = delete;
  ResultsReader& operator=(const ResultsReader&) = delete;

  Index frame_count() const;
  double frame_time(Index frame) const;
  Index frame_step(Index frame) const;
  /// Names of the particle datasets in a frame ("position", "velocity", ...).
  std::vector<std::string> frame_fields(Index frame) const;
  /// Whether a frame holds a dataset or group, e.g. "stress", "voxels", "grid/stress".
  bool frame_has(Index frame, const std::string& path) const;
  /// A dataset as rows x columns, row-major. `field` is a particle dataset ("stress") or a
  /// dataset of a frame's sub-group ("grid/stress", "voxels/corners"). Datasets of rank > 2
  /// fold their leading dimensions into rows (grid/stress, 1 x ny x nx x 6: ny nx rows of 6).
  std::vector<double> read(Index frame, const std::string& field, Index* rows, Index* cols) const;
  std::string case_text() const;
  /// An attribute of /metadata as text (numbers in shortest round-trip form, array entries
  /// separated by single spaces).
  std::string metadata_string(const std::string& name) const;
  /// The same for an attribute of a frame's sub-group, e.g. ("grid", "origin").
  std::string frame_attribute(Index frame, const std::string& group, const std::string& name) const;

private:
  std::string attribute_string(const std::string& group, const std::string& name) const;

  long long file_ = -1; // hid_t, kept opaque so users need no HDF5 headers
};

/// timeseries.csv: one header line, one row per call, flushed so a killed run keeps its rows.
class TimeSeriesWriter {
public:
  /// A writer of no file (a distributed run's ranks other than 0): rows are checked, not written.
  explicit TimeSeriesWriter(std::size_t columns) : columns_(columns) {}
  /// Creates `file` with the header line. `append`: continues an existing file (a resumed run,
  /// which has cut it back to the checkpoint's rows), writing no header.
  TimeSeriesWriter(const std::filesystem::path& file, std::vector<std::string> columns,
                   bool append = false);
  ~TimeSeriesWriter();
  TimeSeriesWriter(const TimeSeriesWriter&) = delete;
  TimeSeriesWriter& operator=(const TimeSeriesWriter&) = delete;
  void append(const std::vector<double>& row);

private:
  std::FILE* file_ = nullptr;
  std::size_t columns_ = 0;
};

/// Writes summary.json atomically (temporary file + rename). Values are already JSON-encoded
/// by the caller through the helpers below, keeping this header free of a JSON library.
/// How one stage of a staged run went (summary.json "stages").
struct StageSummary {
  std::string name;
  std::string analysis;
  double strength_factor = 1;          ///< at the stage's end
  double start_time = 0, end_time = 0; ///< s, run time
  Index steps = 0;                     ///< steps the stage took
  double wall_seconds = 0;
  std::string end; ///< why it ended: end_time, at rest, limit, failure
};

struct RunSummary {
  std::string case_name;
  std::string status; ///< "completed", "numerical_failure", "interrupted", "stopped"
  std::string message;
  Index steps = 0;
  double final_time = 0;
  Index particles = 0;
  Index frames = 0;
  double wall_seconds = 0;
  std::string linear_solver; ///< implicit runs: the linear solver backend used; empty: omitted
  std::map<std::string, double> extra; ///< further numbers (later solvers add timings)
  std::vector<StageSummary> stages;    ///< staged runs only; empty: omitted
};
void write_summary_json(const std::filesystem::path& file, const RunSummary& summary);

} // namespace talus
