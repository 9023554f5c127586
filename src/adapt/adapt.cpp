#include "talus/adapt/adapt.hpp"

#include "talus/core/errors.hpp"
#include "talus/core/scene.hpp"
#include "talus/io/case_reader.hpp"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <fstream>
#include <limits>
#include <set>
#include <utility>

namespace talus {

namespace fs = std::filesystem;

namespace {

using Cell = std::pair<Index, Index>; // (i, j) of a grid cell

/// Per body, the cells of the initial lattice (x0) its points start in.
struct CellMarks {
  std::vector<std::set<Cell>> body_cells, marked;
};

Cell cell_of(const Grid<2>& grid, const Vec2& x) {
  const Vec2 r = (x - grid.origin()) / grid.cell_size();
  return {static_cast<Index>(std::floor(r.x())), static_cast<Index>(std::floor(r.y()))};
}

double voxel_aspect_ratio(const Mat2& F, const Vec2& half_size0) {
  const Mat2 edges = F * half_size0.asDiagonal();
  const Vec2 s = Eigen::JacobiSVD<Mat2>(edges).singularValues();
  return s[0] / s[1];
}

CellMarks mark_cells(const Scene<2>& scene, const AdaptOptions& options) {
  const auto& P = scene.particles;
  std::vector<double> kappa(static_cast<std::size_t>(P.size()), 0.0);
  for (std::size_t m = 0; m < scene.materials.size(); ++m)
    scene.materials[m]->plastic_strain(scene.particles_of_material[m], kappa);
  CellMarks marks;
  marks.body_cells.resize(scene.spec.bodies.size());
  marks.marked.resize(scene.spec.bodies.size());
  for (Index p = 0; p < P.size(); ++p) {
    const auto s = static_cast<std::size_t>(p);
    const auto b = static_cast<std::size_t>(P.body[s]);
    const Cell c = cell_of(scene.grid, P.x0[s]);
    marks.body_cells[b].insert(c);
    if (kappa[s] > options.plastic_strain ||
        voxel_aspect_ratio(P.grid_F(s), P.half_size0[s]) > options.aspect_ratio)
      marks.marked[b].insert(c);
  }
  // The buffer: every body cell within buffer_cells (in both directions) of a marked one.
  const Index r = options.buffer_cells;
  for (std::size_t b = 0; b < marks.marked.size(); ++b) {
    std::set<Cell> grown;
    for (const Cell& c : marks.marked[b])
      for (Index dj = -r; dj <= r; ++dj)
        for (Index di = -r; di <= r; ++di) {
          const Cell n{c.first + di, c.second + dj};
          if (marks.body_cells[b].count(n))
            grown.insert(n);
        }
    marks.marked[b] = std::move(grown);
  }
  return marks;
}

/// The marked cells as boxes, one per run of consecutive cells in a row.
std::vector<std::array<double, 4>> boxes_of(const Grid<2>& grid, const std::set<Cell>& cells) {
  std::vector<std::pair<Index, Index>> by_row; // (j, i), sorted by row then column
  for (const Cell& c : cells)
    by_row.emplace_back(c.second, c.first);
  std::sort(by_row.begin(), by_row.end());
  std::vector<std::array<double, 4>> boxes;
  const double h = grid.cell_size();
  const Vec2 o = grid.origin();
  for (std::size_t k = 0; k < by_row.size();) {
    const Index j = by_row[k].first, i0 = by_row[k].second;
    Index i1 = i0;
    std::size_t next = k + 1;
    while (next < by_row.size() && by_row[next].first == j && by_row[next].second == i1 + 1) {
      ++i1;
      ++next;
    }
    boxes.push_back({o.x() + h * static_cast<double>(i0), o.y() + h * static_cast<double>(j),
                     o.x() + h * static_cast<double>(i1 + 1),
                     o.y() + h * static_cast<double>(j + 1)});
    k = next;
  }
  return boxes;
}

std::string refine_override(const BodySpec& body, int particles_per_cell,
                            const std::vector<std::array<double, 4>>& boxes) {
  std::string list;
  for (const auto& b : boxes)
    list += fmt::format("{}[{}, {}, {}, {}]", list.empty() ? "" : ", ", b[0], b[1], b[2], b[3]);
  return fmt::format("bodies.{}.refine={{particles_per_cell: {}, boxes: [{}]}}", body.name,
                     particles_per_cell, list);
}

/// The material extent at the end: the largest x and y of any deformed voxel corner.
std::pair<double, double> extent_of(const Particles<2>& P) {
  double front = -std::numeric_limits<double>::infinity(), top = front;
  for (Index p = 0; p < P.size(); ++p) {
    const auto s = static_cast<std::size_t>(p);
    for (const double sx : {-1.0, 1.0})
      for (const double sy : {-1.0, 1.0}) {
        const Vec2 corner = P.x[s] + P.grid_F(s) * Vec2(sx, sy).cwiseProduct(P.half_size0[s]);
        front = std::max(front, corner.x());
        top = std::max(top, corner.y());
      }
  }
  return {front, top};
}

AdaptRun run_one(const std::string& label, const CaseSpec& spec, const AdaptOptions& options,
                 const fs::path& root, CellMarks* marks) {
  AdaptRun run;
  run.label = label;
  RunOptions ro;
  ro.out_dir = root / label;
  ro.force = true; // the whole folder was checked (or --force given) before the first run
  ro.threads = options.threads;
  ro.progress = options.progress;
  ro.final_state = [&](const Scene<2>& scene) {
    std::tie(run.front, run.top) = extent_of(scene.particles);
    if (marks)
      *marks = mark_cells(scene, options);
  };
  run.result = run_case(spec, ro);
  run.particles_initial = static_cast<Index>(run.result.extra.count("particles_initial")
                                                 ? run.result.extra.at("particles_initial")
                                                 : static_cast<double>(run.result.particles));
  if (run.result.status != "completed")
    throw NumericalError(fmt::format("talus adapt: the {} run ended with {}: {}", label,
                                     run.result.status, run.result.message));
  return run;
}

void check_options(const AdaptOptions& o) {
  auto bad = [](const std::string& key, const std::string& what) {
    throw InputError({key, 0, 0, ""}, what);
  };
  if (o.factor < 2 || o.factor > 8)
    bad("--factor", fmt::format("must be an integer from 2 to 8 (got {})", o.factor));
  if (!(o.plastic_strain > 0))
    bad("--plastic-strain", fmt::format("must be > 0 (got {:g})", o.plastic_strain));
  if (!(o.aspect_ratio > 1))
    bad("--aspect-ratio", fmt::format("must be > 1 (got {:g})", o.aspect_ratio));
  if (o.buffer_cells < 0 || o.buffer_cells > 10)
    bad("--buffer", fmt::format("must be an integer from 0 to 10 (got {})", o.buffer_cells));
}

} // namespace

AdaptReport adapt_case(const std::string& case_file, const std::vector<std::string>& overrides,
                       const AdaptOptions& options) {
  check_options(options);
  const CaseSpec coarse = read_case_file(case_file, overrides);
  for (const BodySpec& b : coarse.bodies)
    if (b.particles_per_cell * options.factor > 16)
      throw InputError(b.where, fmt::format("body '{}': {} points per cell times --factor {} "
                                            "exceeds the limit of 16 per direction",
                                            b.name, b.particles_per_cell, options.factor));
  const fs::path root =
      options.out_dir.empty() ? fs::path("results") / (coarse.name + "_adapt") : options.out_dir;
  prepare_output_directory(root, options.force);
  for (const char* label : {"coarse", "adapted", "fine"})
    prepare_output_directory(root / label, options.force);

  AdaptReport report;
  CellMarks marks;
  report.runs.push_back(run_one("coarse", coarse, options, root, &marks));

  report.overrides = overrides;
  for (std::size_t b = 0; b < coarse.bodies.size(); ++b) {
    report.body_cells += static_cast<Index>(marks.body_cells[b].size());
    report.marked_cells += static_cast<Index>(marks.marked[b].size());
    if (marks.marked[b].empty())
      continue;
    const BodySpec& body = coarse.bodies[b];
    report.overrides.push_back(
        refine_override(body, body.particles_per_cell * options.factor,
                        boxes_of(build_scene<2>(coarse).grid, marks.marked[b])));
  }
  const CaseSpec adapted = read_case_file(case_file, report.overrides);
  report.runs.push_back(run_one("adapted", adapted, options, root, nullptr));

  if (options.benchmark) {
    std::vector<std::string> fine_overrides = overrides;
    for (const BodySpec& b : coarse.bodies)
      fine_overrides.push_back(fmt::format("bodies.{}.particles_per_cell={}", b.name,
                                           b.particles_per_cell * options.factor));
    report.runs.push_back(
        run_one("fine", read_case_file(case_file, fine_overrides), options, root, nullptr));
  }

  std::ofstream md(root / "adapt.md");
  md << "# talus adapt: " << coarse.name << "\n\n"
     << fmt::format("Marked {} of {} body cells (plastic strain > {:g} or voxel aspect ratio > "
                    "{:g} at the end of the coarse pre-run, plus {} cell(s) around); {} times "
                    "the points per direction there.\n\n",
                    report.marked_cells, report.body_cells, options.plastic_strain,
                    options.aspect_ratio, options.buffer_cells, options.factor)
     << "Adapted case: `talus run " << case_file;
  for (const std::string& o : report.overrides)
    md << " --set '" << o << "'";
  md << "`\n\n" << adapt_table(report);
  return report;
}

std::string adapt_table(const AdaptReport& report) {
  const AdaptRun* fine = nullptr;
  for (const AdaptRun& r : report.runs)
    if (r.label == "fine")
      fine = &r;
  std::string out = "| run | points t=0 | points end | wall time [s] | front [m] | top [m]";
  out += fine ? " | front error [m] | top error [m] |\n|---|---|---|---|---|---|---|---|\n"
              : " |\n|---|---|---|---|---|---|\n";
  double pre_seconds = 0;
  for (const AdaptRun& r : report.runs) {
    // The adapted workflow costs its pre-run too.
    const double seconds = r.result.wall_seconds + (r.label == "adapted" ? pre_seconds : 0.0);
    if (r.label == "coarse")
      pre_seconds = r.result.wall_seconds;
    out += fmt::format("| {}{} | {} | {} | {:.2f} | {:.4f} | {:.4f}", r.label,
                       r.label == "adapted" ? " (incl. pre-run)" : "", r.particles_initial,
                       r.result.particles, seconds, r.front, r.top);
    if (fine)
      out += fmt::format(" | {:.4f} | {:.4f}", std::abs(r.front - fine->front),
                         std::abs(r.top - fine->top));
    out += " |\n";
  }
  return out;
}

} // namespace talus
