// A run's checkpoints (run_checkpoint.hpp).
#include "run_checkpoint.hpp"

#include "talus/core/errors.hpp"
#include "talus/io/case_reader.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <limits>
#include <nlohmann/json.hpp>

namespace talus::run_detail {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

/// Checkpoints kept: the newest, and the one before in case the newest is damaged.
constexpr std::size_t kKept = 2;

/// The entry's layout version: a checkpoint of another layout is refused, not misread.
constexpr int kProgressVersion = 2;

// JSON has no NaN: a value not measured yet is null.
json finite_or_null(double x) {
  return std::isfinite(x) ? json(x) : json();
}
double number_or_nan(const json& j) {
  return j.is_null() ? std::numeric_limits<double>::quiet_NaN() : j.get<double>();
}

json frame_json(const ResultsWriter::FrameRecord& f) {
  std::vector<int> fields;
  for (const OutputField field : f.fields)
    fields.push_back(static_cast<int>(field));
  return {{"step", f.step},
          {"time", f.time},
          {"particles", f.particles},
          {"fields", fields},
          {"recovered", f.recovered},
          {"voxels", f.voxels},
          {"grid_nodes", f.grid_nodes},
          {"grid_origin", {f.grid_origin.x(), f.grid_origin.y(), f.grid_origin.z()}}};
}

ResultsWriter::FrameRecord frame_of(const json& j) {
  ResultsWriter::FrameRecord f;
  f.step = j.at("step");
  f.time = j.at("time");
  f.particles = j.at("particles");
  for (const int field : j.at("fields").get<std::vector<int>>())
    f.fields.push_back(static_cast<OutputField>(field));
  f.recovered = j.at("recovered");
  f.voxels = j.at("voxels");
  f.grid_nodes = j.at("grid_nodes");
  const auto o = j.at("grid_origin").get<std::vector<double>>();
  f.grid_origin = Vec3(o.at(0), o.at(1), o.at(2));
  return f;
}

json stage_json(const StageSummary& s) {
  return {{"name", s.name},
          {"analysis", s.analysis},
          {"strength_factor", s.strength_factor},
          {"start_time", s.start_time},
          {"end_time", s.end_time},
          {"steps", s.steps},
          {"wall_seconds", s.wall_seconds},
          {"end", s.end}};
}

StageSummary stage_of(const json& j) {
  StageSummary s;
  s.name = j.at("name");
  s.analysis = j.at("analysis");
  s.strength_factor = j.at("strength_factor");
  s.start_time = j.at("start_time");
  s.end_time = j.at("end_time");
  s.steps = j.at("steps");
  s.wall_seconds = j.at("wall_seconds");
  s.end = j.at("end");
  return s;
}

/// Keys a resumed run may change with --accept-changes: how long it runs and what it writes,
/// never the physics of the steps already taken.
bool safe_change(std::string key) {
  if (key == "output" || key.starts_with("output."))
    return true;
  // stages[i].time.end_time, stages[i].wall_time_limit, ...: the same keys as the case's own.
  if (key.starts_with("stages[")) {
    const std::size_t close = key.find("].");
    if (close == std::string::npos || close == 7 ||
        !std::all_of(key.begin() + 7, key.begin() + static_cast<long>(close),
                     [](unsigned char c) { return std::isdigit(c) != 0; }))
      return false;
    key = key.substr(close + 2);
    if (key == "wall_time_limit")
      return true;
  }
  return key == "time.end_time" || key == "time.max_steps";
}

} // namespace

fs::path checkpoint_dir(const fs::path& out_dir) {
  return out_dir / "checkpoints";
}

void put_progress(CheckpointWriter& out, const RunProgress& p) {
  json j;
  j["version"] = kProgressVersion;
  j["case_text"] = p.case_text;
  j["overrides"] = p.overrides;
  j["dimension"] = p.dimension;
  j["stage"] = p.stage;
  j["stage_started"] = p.stage_started;
  j["step"] = p.loop.step;
  j["stage_first_step"] = p.loop.stage_first_step;
  j["t"] = p.loop.t;
  j["stage_start_time"] = p.stage_start_time;
  j["strength_factor"] = p.strength_factor;
  j["stage_start_strength"] = p.stage_start_strength;
  j["stage_wall_seconds"] = p.stage_wall_seconds;
  j["wall_seconds"] = p.wall_seconds;
  j["linear_solver"] = p.linear_solver;
  j["implicit_dt"] = p.loop.load_step.dt;
  j["easy_steps"] = p.loop.load_step.easy_steps;
  j["prescribed_fraction"] = p.loop.continuation.prescribed_fraction;
  j["line_search_first"] = p.loop.continuation.line_search_first;
  j["reference_compliance"] = finite_or_null(p.loop.reference_compliance);
  j["current_stiffness"] = finite_or_null(p.loop.current_stiffness);
  j["peak_kinetic"] = p.watch.peak_kinetic;
  j["quiet_since"] = p.watch.quiet_since ? json(*p.watch.quiet_since) : json();
  j["extra"] = p.extra;
  j["stages"] = json::array();
  for (const auto& s : p.stages)
    j["stages"].push_back(stage_json(s));
  j["frames"] = json::array();
  for (const auto& f : p.frames)
    j["frames"].push_back(frame_json(f));
  j["timeseries_bytes"] = p.timeseries_bytes;
  j["newton_log_bytes"] = p.newton_log_bytes;
  j["next_frame_time"] = p.schedule.next_frame_time;
  j["frame_at_current_step"] = p.schedule.frame_at_current_step;
  j["last_frame_step"] = p.schedule.last_frame_step;
  j["last_frame_time"] = p.schedule.last_frame_time;
  j["frame_seconds"] = p.schedule.frame_seconds;
  j["post_seconds"] = p.schedule.post_seconds;
  out.put_text("run", j.dump());
}

RunProgress read_progress(const CheckpointReader& in) {
  const json j = json::parse(in.text("run"));
  if (j.at("version") != kProgressVersion)
    throw std::runtime_error(
        fmt::format("checkpoint '{}' has layout version {}, this Talus reads {}",
                    in.file().string(), j.at("version").dump(), kProgressVersion));
  RunProgress p;
  p.case_text = j.at("case_text");
  p.overrides = j.at("overrides");
  p.dimension = j.at("dimension");
  p.stage = j.at("stage");
  p.stage_started = j.at("stage_started");
  p.loop.step = j.at("step");
  p.loop.stage_first_step = j.at("stage_first_step");
  p.loop.t = j.at("t");
  p.stage_start_time = j.at("stage_start_time");
  p.strength_factor = j.at("strength_factor");
  p.stage_start_strength = j.at("stage_start_strength");
  p.stage_wall_seconds = j.at("stage_wall_seconds");
  p.wall_seconds = j.at("wall_seconds");
  p.linear_solver = j.at("linear_solver");
  p.loop.load_step.dt = j.at("implicit_dt");
  p.loop.load_step.easy_steps = j.at("easy_steps");
  p.loop.continuation.prescribed_fraction = j.at("prescribed_fraction");
  p.loop.continuation.line_search_first = j.at("line_search_first");
  p.loop.reference_compliance = number_or_nan(j.at("reference_compliance"));
  p.loop.current_stiffness = number_or_nan(j.at("current_stiffness"));
  p.watch.peak_kinetic = j.at("peak_kinetic");
  if (!j.at("quiet_since").is_null())
    p.watch.quiet_since = j.at("quiet_since").get<double>();
  p.extra = j.at("extra").get<std::map<std::string, double>>();
  for (const auto& s : j.at("stages"))
    p.stages.push_back(stage_of(s));
  for (const auto& f : j.at("frames"))
    p.frames.push_back(frame_of(f));
  p.timeseries_bytes = j.at("timeseries_bytes");
  p.newton_log_bytes = j.at("newton_log_bytes");
  p.schedule.next_frame_time = j.at("next_frame_time");
  p.schedule.frame_at_current_step = j.at("frame_at_current_step");
  p.schedule.last_frame_step = j.at("last_frame_step");
  p.schedule.last_frame_time = j.at("last_frame_time");
  p.schedule.frame_seconds = j.at("frame_seconds");
  p.schedule.post_seconds = j.at("post_seconds");
  return p;
}

fs::path checkpoint_file(const fs::path& out_dir, Index step) {
  const fs::path dir = checkpoint_dir(out_dir);
  fs::create_directories(dir);
  return dir / checkpoint_name(step);
}

void prune_checkpoints(const fs::path& out_dir) {
  const auto all = list_checkpoints(checkpoint_dir(out_dir));
  std::error_code ec;
  for (std::size_t k = kKept; k < all.size(); ++k)
    fs::remove(all[k], ec);
}

CheckpointReader newest_valid_checkpoint(const fs::path& out_dir,
                                         std::vector<std::string>& skipped) {
  const fs::path dir = checkpoint_dir(out_dir);
  for (const fs::path& file : list_checkpoints(dir)) {
    std::string why;
    if (auto reader = CheckpointReader::open(file, why)) {
      try {
        read_progress(*reader);
        return std::move(*reader);
      } catch (const std::exception& e) {
        why = e.what();
      }
    }
    skipped.push_back(fmt::format("skipped checkpoint '{}': it {}", file.string(), why));
  }
  throw InputError({"--resume", 0, 0, ""},
                   fmt::format("no usable checkpoint in '{}'{}{}", dir.string(),
                               skipped.empty() ? "" : "; ", fmt::join(skipped, "; ")));
}

void check_same_case(const CaseSpec& spec, const RunProgress& progress, bool accept_changes) {
  const std::vector<std::string> changed =
      case_differences(progress.case_text, progress.overrides, spec.source_text, spec.overrides);
  if (changed.empty())
    return;
  std::vector<std::string> unsafe;
  for (const auto& key : changed)
    if (!safe_change(key))
      unsafe.push_back(key);
  if (unsafe.empty() && accept_changes)
    return;
  throw InputError(
      {"--resume", 0, 0, ""},
      unsafe.empty()
          ? fmt::format("the case differs from the one the run started with at {}; these keys "
                        "may change on a resume: pass --accept-changes to continue with them",
                        fmt::join(changed, ", "))
          : fmt::format("the case differs from the one the run started with at {}; a resumed "
                        "run must keep the physics of its steps (only end times, max_steps, "
                        "wall-time limits and output may change, with --accept-changes)",
                        fmt::join(unsafe, ", ")));
}

} // namespace talus::run_detail
