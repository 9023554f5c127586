#include "talus/adapt/adapt.hpp"

#include "talus/core/errors.hpp"
#include "talus/io/case_reader.hpp"
#include "talus/scene/scene.hpp"

#include <Eigen/SVD>
#include <algorithm>
#include <array>
#include <cmath>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <fstream>
#include <limits>
#include <set>
#include <utility>

namespace talus {

namespace fs = std::filesystem;

namespace {

template <int Dim> using Cell = std::array<Index, Dim>; // (i, j[, k]) of a grid cell

/// Per body, the cells of the initial lattice (x0) its points start in.
template <int Dim> struct CellMarks { std::vector<std::set<Cell<Dim>>> body_cells, marked; };

template <int Dim> Cell<Dim> cell_of(const Grid<Dim>& grid, const Vec<Dim>& x) {
  const Vec<Dim> r = (x - grid.origin()) / grid.cell_size();
  Cell<Dim> c{};
  for (int d = 0; d < Dim; ++d)
    c[static_cast<std::size_t>(d)] = static_cast<Index>(std::floor(r[d]));
  return c;
}

/// Long over short singular value of the deformed voxel's edges F diag(h0).
template <int Dim> double voxel_aspect_ratio(const Mat<Dim>& F, const Vec<Dim>& half_size0) {
  const Mat<Dim> edges = F * half_size0.asDiagonal();
  const Vec<Dim> s = Eigen::JacobiSVD<Mat<Dim>>(edges).singularValues();
  return s[0] / s[Dim - 1];
}

template <int Dim> CellMarks<Dim> mark_cells(const Scene<Dim>& scene, const AdaptOptions& options) {
  const auto& P = scene.particles;
  std::vector<double> kappa(static_cast<std::size_t>(P.size()), 0.0);
  for (std::size_t m = 0; m < scene.materials.size(); ++m)
    scene.materials[m]->plastic_strain(scene.particles_of_material[m], kappa);
  CellMarks<Dim> marks;
  marks.body_cells.resize(scene.spec.bodies.size());
  marks.marked.resize(scene.spec.bodies.size());
  for (Index p = 0; p < P.size(); ++p) {
    const auto s = static_cast<std::size_t>(p);
    const auto b = static_cast<std::size_t>(P.body[s]);
    const Cell<Dim> c = cell_of<Dim>(scene.grid, P.x0[s]);
    marks.body_cells[b].insert(c);
    if (kappa[s] > options.plastic_strain ||
        voxel_aspect_ratio<Dim>(P.grid_F(s), P.half_size0[s]) > options.aspect_ratio)
      marks.marked[b].insert(c);
  }
  // The buffer: every body cell within buffer_cells (along every axis) of a marked one.
  const Index r = options.buffer_cells;
  Index offsets = 1;
  for (int d = 0; d < Dim; ++d)
    offsets *= 2 * r + 1;
  for (std::size_t b = 0; b < marks.marked.size(); ++b) {
    std::set<Cell<Dim>> grown;
    for (const Cell<Dim>& c : marks.marked[b])
      for (Index k = 0; k < offsets; ++k) {
        Cell<Dim> n = c;
        for (Index d = 0, rest = k; d < Dim; ++d, rest /= 2 * r + 1)
          n[static_cast<std::size_t>(d)] += rest % (2 * r + 1) - r;
        if (marks.body_cells[b].count(n))
          grown.insert(n);
      }
    marks.marked[b] = std::move(grown);
  }
  return marks;
}

/// The marked cells as boxes (lower corner, then upper, 2 Dim numbers), one per run of cells
/// consecutive along x with the same other indices.
template <int Dim>
std::vector<std::vector<double>> boxes_of(const Grid<Dim>& grid, const std::set<Cell<Dim>>& cells) {
  // Ordered by the last axis first and x last, so that runs along x are adjacent.
  std::vector<Cell<Dim>> rows(cells.begin(), cells.end());
  std::sort(rows.begin(), rows.end(), [](const Cell<Dim>& a, const Cell<Dim>& b) {
    return std::lexicographical_compare(a.rbegin(), a.rend(), b.rbegin(), b.rend());
  });
  std::vector<std::vector<double>> boxes;
  const double h = grid.cell_size();
  const Vec<Dim> o = grid.origin();
  for (std::size_t k = 0; k < rows.size();) {
    const Cell<Dim> first = rows[k];
    Cell<Dim> last = first;
    std::size_t next = k + 1;
    while (next < rows.size() &&
           std::equal(first.begin() + 1, first.end(), rows[next].begin() + 1) &&
           rows[next][0] == last[0] + 1)
      last = rows[next++];
    std::vector<double> box(2 * Dim);
    for (std::size_t d = 0; d < Dim; ++d) {
      box[d] = o[static_cast<int>(d)] + h * static_cast<double>(first[d]);
      box[Dim + d] = o[static_cast<int>(d)] + h * static_cast<double>(last[d] + 1);
    }
    boxes.push_back(std::move(box));
    k = next;
  }
  return boxes;
}

std::string refine_override(const BodySpec& body, int particles_per_cell,
                            const std::vector<std::vector<double>>& boxes) {
  std::string list;
  for (const auto& b : boxes)
    list += fmt::format("{}[{}]", list.empty() ? "" : ", ", fmt::join(b, ", "));
  return fmt::format("bodies.{}.refine={{particles_per_cell: {}, boxes: [{}]}}", body.name,
                     particles_per_cell, list);
}

/// The material extent at the end: the largest x and y of any deformed voxel corner.
template <int Dim> std::pair<double, double> extent_of(const Particles<Dim>& P) {
  double front = -std::numeric_limits<double>::infinity(), top = front;
  for (Index p = 0; p < P.size(); ++p) {
    const auto s = static_cast<std::size_t>(p);
    for (int corner = 0; corner < (1 << Dim); ++corner) {
      Vec<Dim> sign;
      for (int d = 0; d < Dim; ++d)
        sign[d] = (corner >> d) & 1 ? 1.0 : -1.0;
      const Vec<Dim> x = P.x[s] + P.grid_F(s) * sign.cwiseProduct(P.half_size0[s]);
      front = std::max(front, x.x());
      top = std::max(top, x.y());
    }
  }
  return {front, top};
}

template <int Dim>
AdaptRun run_one(const std::string& label, const CaseSpec& spec, const AdaptOptions& options,
                 const fs::path& root, CellMarks<Dim>* marks) {
  AdaptRun run;
  run.label = label;
  RunOptions ro;
  ro.out_dir = root / label;
  ro.force = true; // the whole folder was checked (or --force given) before the first run
  ro.threads = options.threads;
  ro.progress = options.progress;
  const auto inspect = [&](const Scene<Dim>& scene) {
    std::tie(run.front, run.top) = extent_of<Dim>(scene.particles);
    if (marks)
      *marks = mark_cells<Dim>(scene, options);
  };
  if constexpr (Dim == 2)
    ro.final_state = inspect;
  else
    ro.final_state_3d = inspect;
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

/// The pre-run, the marks and the adapted (and fine) runs of a case of dimension Dim.
template <int Dim>
AdaptReport adapt_in(const std::string& case_file, const std::vector<std::string>& overrides,
                     const AdaptOptions& options, const CaseSpec& coarse, const fs::path& root) {
  AdaptReport report;
  CellMarks<Dim> marks;
  report.runs.push_back(run_one<Dim>("coarse", coarse, options, root, &marks));

  report.overrides = overrides;
  for (std::size_t b = 0; b < coarse.bodies.size(); ++b) {
    report.body_cells += static_cast<Index>(marks.body_cells[b].size());
    report.marked_cells += static_cast<Index>(marks.marked[b].size());
    if (marks.marked[b].empty())
      continue;
    const BodySpec& body = coarse.bodies[b];
    report.overrides.push_back(
        refine_override(body, body.particles_per_cell * options.factor,
                        boxes_of<Dim>(build_scene<Dim>(coarse).grid, marks.marked[b])));
  }
  const CaseSpec adapted = read_case_file(case_file, report.overrides);
  report.runs.push_back(run_one<Dim>("adapted", adapted, options, root, nullptr));

  if (options.benchmark) {
    std::vector<std::string> fine_overrides = overrides;
    for (const BodySpec& b : coarse.bodies)
      fine_overrides.push_back(fmt::format("bodies.{}.particles_per_cell={}", b.name,
                                           b.particles_per_cell * options.factor));
    report.runs.push_back(
        run_one<Dim>("fine", read_case_file(case_file, fine_overrides), options, root, nullptr));
  }

  return report;
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

  AdaptReport report = coarse.dimension == 3
                           ? adapt_in<3>(case_file, overrides, options, coarse, root)
                           : adapt_in<2>(case_file, overrides, options, coarse, root);
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
