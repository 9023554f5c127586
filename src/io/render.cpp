// `talus render` (include/talus/io/render.hpp): resolves the frame, field, component, pattern,
// mode and (3D) slice or view against run.h5, then hands the resolved datasets to
// scripts/render.py.
#include "talus/io/render.hpp"

#include "talus/core/errors.hpp"
#include "talus/io/results.hpp"
#include "talus/post/python_script.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <limits>
#include <numeric>
#include <optional>
#include <vector>

namespace talus {

namespace fs = std::filesystem;

namespace {

[[noreturn]] void bad(const std::string& option, const std::string& what) {
  throw InputError({option, 0, 0, ""}, what);
}

/// Component names of a dataset by its column count, in column order; an axisymmetric run's
/// by r, z and t (the hoop direction theta): x is r, y is z, the third axis is theta.
std::vector<std::string> components_of(Index columns, bool axisymmetric) {
  if (axisymmetric)
    switch (columns) {
    case 2:
      return {"r", "z"};
    case 6: // Tensor6: rr, rz, rt, zz, zt, tt
      return {"rr", "rz", "rt", "zz", "zt", "tt"};
    case 9:
      return {"rr", "rz", "rt", "zr", "zz", "zt", "tr", "tz", "tt"};
    default:
      break;
    }
  switch (columns) {
  case 2:
    return {"x", "y"};
  case 3:
    return {"x", "y", "z"};
  case 6: // Tensor6: xx, xy, xz, yy, yz, zz
    return {"xx", "xy", "xz", "yy", "yz", "zz"};
  case 9: // 3x3 row-major
    return {"xx", "xy", "xz", "yx", "yy", "yz", "zx", "zy", "zz"};
  default:
    return {};
  }
}

std::vector<Index> selected_frames(const std::string& frame, Index count) {
  if (count == 0)
    bad("--frame", "the results file has no frames");
  if (frame == "last")
    return {count - 1};
  if (frame == "all") {
    std::vector<Index> all(static_cast<std::size_t>(count));
    for (Index k = 0; k < count; ++k)
      all[static_cast<std::size_t>(k)] = k;
    return all;
  }
  Index k = -1;
  const auto [end, ec] = std::from_chars(frame.data(), frame.data() + frame.size(), k);
  if (ec != std::errc() || end != frame.data() + frame.size())
    bad("--frame", fmt::format("expected a frame number, 'last' or 'all', got '{}'", frame));
  if (k < 0 || k >= count)
    bad("--frame", fmt::format("frame {} is not in the results (frames 0 to {})", k, count - 1));
  return {k};
}

/// A 3D slice plane, `--slice z=0.5`: coordinate `axis` (0, 1, 2 for x, y, z) equals `value`.
struct Plane {
  int axis = 0;
  double value = 0;
};

Plane parse_slice(const std::string& text) {
  const std::string axes = "xyz";
  if (text.size() < 2 || text[1] != '=' || axes.find(text[0]) == std::string::npos)
    bad("--slice",
        fmt::format("expected AXIS=VALUE with AXIS x, y or z (e.g. z=0.5), got '{}'", text));
  const char* first = text.data() + (text.size() > 2 && text[2] == '+' ? 3 : 2);
  const char* last = text.data() + text.size();
  double value = 0;
  const auto [end, ec] = std::from_chars(first, last, value);
  if (ec != std::errc() || end != last || !std::isfinite(value))
    bad("--slice", fmt::format("expected a number after '{}=', got '{}'", text[0], text.substr(2)));
  return {static_cast<int>(axes.find(text[0])), value};
}

/// Refuses a plane that misses what is drawn (`dataset`: the voxel corners or the points) in
/// every selected frame; a plane that meets some frames of a sequence draws those.
void check_plane_meets(const ResultsReader& reader, const std::vector<Index>& frames,
                       const std::string& dataset, const Plane& plane) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const Index k : frames) {
    Index rows = 0, columns = 0;
    const std::vector<double> data = reader.read(k, dataset, &rows, &columns);
    double frame_lo = std::numeric_limits<double>::infinity(), frame_hi = -frame_lo;
    for (Index r = 0; r < rows; ++r) {
      frame_lo = std::min(frame_lo, data[static_cast<std::size_t>(r * columns + plane.axis)]);
      frame_hi = std::max(frame_hi, data[static_cast<std::size_t>(r * columns + plane.axis)]);
    }
    if (frame_lo <= plane.value && plane.value <= frame_hi)
      return;
    lo = std::min(lo, frame_lo);
    hi = std::max(hi, frame_hi);
  }
  const char axis = "xyz"[plane.axis];
  bad("--slice", fmt::format("the plane {} = {:g} is outside the {} of {} ({} from {:g} to {:g})",
                             axis, plane.value, dataset == "position" ? "points" : "voxels",
                             frames.size() == 1 ? fmt::format("frame {}", frames.front())
                                                : std::string("every selected frame"),
                             axis, lo, hi));
}

/// Whether the field's drawn values (a column, or the norm of each row) have a positive one in
/// some selected frame: a log scale starts there.
bool any_positive(const ResultsReader& reader, const std::vector<Index>& frames,
                  const std::string& field, const std::string& column) {
  for (const Index k : frames) {
    Index rows = 0, columns = 0;
    const std::vector<double> data = reader.read(k, field, &rows, &columns);
    for (Index r = 0; r < rows; ++r) {
      const double* row = data.data() + r * columns;
      double v = 0;
      if (column == "norm")
        v = std::sqrt(std::inner_product(row, row + columns, row, 0.0));
      else
        v = row[column.empty() ? 0 : std::stoi(column)];
      if (v > 0)
        return true;
    }
  }
  return false;
}

/// The slice that shows what changed in a 3D run: z through the point that moved the most
/// from frame 0 to `frame` (the same point ids: the points of frame 0 that are still there).
Plane slice_through_largest_change(const ResultsReader& reader, Index frame) {
  Index rows0 = 0, rows = 0, columns = 0;
  const std::vector<double> x0 = reader.read(0, "position", &rows0, &columns);
  const std::vector<double> x = reader.read(frame, "position", &rows, &columns);
  double largest = -1, z = 0;
  for (Index r = 0; r < std::min(rows0, rows); ++r) {
    const auto at = static_cast<std::size_t>(r * columns);
    const double moved = std::hypot(x[at] - x0[at], x[at + 1] - x0[at + 1], x[at + 2] - x0[at + 2]);
    if (moved > largest) {
      largest = moved;
      z = x[at + 2];
    }
  }
  return {2, z};
}

/// --clim LO HI (LO < HI, finite; LO > 0 for --log) and --crop X0 Y0 X1 Y1 (X0 < X1, Y0 < Y1).
void check_ranges(const RenderOptions& o) {
  if (!o.clim.empty() && !(o.clim.size() == 2 && std::isfinite(o.clim[0]) &&
                           std::isfinite(o.clim[1]) && o.clim[0] < o.clim[1]))
    bad("--clim", "expected two finite values LO HI with LO < HI");
  if (o.log && !o.clim.empty() && !(o.clim[0] > 0))
    bad("--clim", fmt::format("a logarithmic scale (--log) needs LO > 0, got {:g}", o.clim[0]));
  if (!o.crop.empty() && !(o.crop.size() == 4 && o.crop[0] < o.crop[2] && o.crop[1] < o.crop[3]))
    bad("--crop", "expected X0 Y0 X1 Y1 with X0 < X1 and Y0 < Y1");
  if (o.log && o.delta && o.clim.empty())
    bad("--log", "a change since frame 0 has both signs: give --clim LO HI with LO > 0 for a log "
                 "scale of it");
  if (!o.pattern.empty() && (o.log || o.delta || !o.clim.empty()))
    bad(o.log     ? "--log"
        : o.delta ? "--delta"
                  : "--clim",
        "a pattern has two colours and no scale; --clim, --log and --delta colour a --field");
}

} // namespace

int render(const RenderOptions& o) {
  const std::string file = o.results.string();
  std::error_code ec;
  if (!fs::is_regular_file(o.results, ec))
    bad(file, "no such results file");
  std::optional<ResultsReader> reader;
  try {
    reader.emplace(o.results);
  } catch (const std::runtime_error& e) {
    bad(file, e.what());
  }
  if (o.output.extension() != ".png")
    bad("-o", fmt::format("the picture must be a .png file, got '{}'", o.output.string()));
  if (o.field.empty() == o.pattern.empty())
    bad("--field", "give exactly one of --field NAME and --pattern NAME");
  const std::vector<std::string> patterns = {"checker", "stripes_horizontal", "stripes_vertical"};
  if (!o.pattern.empty() &&
      std::find(patterns.begin(), patterns.end(), o.pattern) == patterns.end())
    bad("--pattern",
        fmt::format("unknown pattern '{}' (allowed: {})", o.pattern, fmt::join(patterns, ", ")));
  if (!o.mode.empty() && o.mode != "voxels" && o.mode != "points")
    bad("--mode", fmt::format("unknown mode '{}' (allowed: voxels, points)", o.mode));
  const bool three_d = reader->metadata_string("dimension") == "3";
  bool axisymmetric = false;
  try { // run.h5 files written before the geometry attribute are plane strain or 3D
    axisymmetric = reader->metadata_string("geometry") == "axisymmetric";
  } catch (const std::runtime_error&) {
  }
  if (!three_d && !o.slice.empty())
    bad("--slice", fmt::format("'{}' is a 2D result: it is drawn in its plane, a slice needs a "
                               "3D run",
                               file));
  if (!three_d && !o.view.empty())
    bad("--view", fmt::format("'{}' is a 2D result: it is drawn in its plane, a view direction "
                              "needs a 3D run",
                              file));
  const std::vector<std::string> views = {"iso", "x", "y", "z"};
  if (!o.view.empty() && std::find(views.begin(), views.end(), o.view) == views.end())
    bad("--view", fmt::format("unknown view '{}' (allowed: {})", o.view, fmt::join(views, ", ")));
  if (!o.view.empty() && !o.slice.empty())
    bad("--view", "a slice is drawn in its plane; --view directs the outer-face view, without "
                  "--slice");
  check_ranges(o);
  const std::vector<Index> frames = selected_frames(o.frame, reader->frame_count());
  // A 3D run without --slice or --view: the slice through the largest change, not the outer
  // faces, where a footing's block looks the same before and after.
  const bool changed_slice = three_d && o.slice.empty() && o.view.empty();
  const Plane plane = !o.slice.empty() ? parse_slice(o.slice)
                      : changed_slice  ? slice_through_largest_change(*reader, frames.back())
                                       : Plane{};
  if (!o.crop.empty() && o.view == "iso")
    bad("--crop", "the iso view has no model axes to crop in; use --slice or --view x, y or z");
  bool all_have_voxels = true;
  for (const Index k : frames)
    all_have_voxels = all_have_voxels && reader->frame_has(k, "voxels");
  const std::string mode = o.mode.empty() ? (all_have_voxels ? "voxels" : "points") : o.mode;
  const bool needs_voxels = mode == "voxels" || !o.pattern.empty();
  if (needs_voxels && !all_have_voxels)
    bad(o.pattern.empty() ? "--mode" : "--pattern",
        fmt::format("'{}' has no voxels in {}; run the case with 'output: {{voxels: true}}' "
                    "(or draw dots with --mode points)",
                    file, o.frame == "all" ? "every frame" : "frame " + o.frame));

  std::vector<std::string> args = {o.results.string(), "--frames"};
  for (const Index k : frames)
    args.push_back(std::to_string(k));
  if (!o.pattern.empty()) {
    args.insert(args.end(), {"--pattern", o.pattern});
    if (!o.component.empty())
      bad("--component", "a pattern has no components");
  } else {
    // The field must be a particle dataset of every selected frame.
    Index columns = 0;
    for (const Index k : frames) {
      const auto names = reader->frame_fields(k);
      if (std::find(names.begin(), names.end(), o.field) == names.end())
        bad("--field", fmt::format("field '{}' is not in frame {} of '{}' (it has: {})", o.field, k,
                                   file, fmt::join(names, ", ")));
    }
    Index rows = 0;
    reader->read(frames.front(), o.field, &rows, &columns);
    const auto names = components_of(columns, axisymmetric);
    std::string column;
    std::string label = o.field;
    if (names.empty()) {
      if (!o.component.empty())
        bad("--component", fmt::format("field '{}' is a scalar; leave out --component", o.field));
    } else if (o.component.empty() || o.component == "magnitude") {
      if (columns > 3)
        bad("--component", fmt::format("field '{}' has components {}; choose one with --component",
                                       o.field, fmt::join(names, ", ")));
      column = "norm";
      label += " magnitude";
    } else {
      const auto it = std::find(names.begin(), names.end(), o.component);
      if (it == names.end())
        bad("--component",
            fmt::format("field '{}' has no component '{}' (allowed: {}{})", o.field, o.component,
                        fmt::join(names, ", "), columns <= 3 ? ", magnitude" : ""));
      column = std::to_string(it - names.begin());
      label += " " + o.component;
    }
    args.insert(args.end(), {"--dataset", o.field, "--column", column, "--label", label});
    if (o.delta)
      for (const Index k : frames) {
        Index rows0 = 0, rows_k = 0, c = 0;
        reader->read(0, o.field, &rows0, &c);
        reader->read(k, o.field, &rows_k, &c);
        if (rows0 != rows_k)
          bad("--delta", fmt::format("frame {} has {} points and frame 0 {} (points split): a "
                                     "change since frame 0 needs the same points",
                                     k, rows_k, rows0));
      }
    if (o.log && o.clim.empty() && !o.delta && !any_positive(*reader, frames, o.field, column))
      bad("--log", fmt::format("field '{}' has no positive value in the frames drawn; a log scale "
                               "needs some (or give --clim LO HI)",
                               label));
  }
  if (!o.slice.empty() || changed_slice) {
    check_plane_meets(*reader, frames, mode == "voxels" ? "voxels/corners" : "position", plane);
    args.insert(args.end(), {"--slice", fmt::format("{}={:.17g}", "xyz"[plane.axis], plane.value)});
  } else if (three_d) {
    args.insert(args.end(), {"--view", o.view.empty() ? "iso" : o.view});
  }
  if (axisymmetric)
    args.push_back("--axisymmetric");
  if (!o.clim.empty())
    args.insert(args.end(),
                {"--clim", fmt::format("{:.17g}", o.clim[0]), fmt::format("{:.17g}", o.clim[1])});
  if (o.log)
    args.push_back("--log");
  if (o.delta)
    args.push_back("--delta");
  if (!o.crop.empty()) {
    args.push_back("--crop");
    for (const double c : o.crop)
      args.push_back(fmt::format("{:.17g}", c));
  }
  args.insert(args.end(), {"--mode", mode, "-o", o.output.string()});
  if (o.frame == "all")
    args.push_back("--sequence");
  if (o.output.has_parent_path())
    fs::create_directories(o.output.parent_path());
  run_python_script("render.py", args);
  return kExitOk;
}

} // namespace talus
