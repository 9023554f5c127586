// YAML case file -> validated CaseSpec. The schema and every rule enforced here are documented in
// docs/case-format.md; keep the two in step. The Validator (validator.hpp) reads the sections in
// read_*.cpp; this file holds the checked Map, the top level of the case and the entry points.
#include "talus/io/case_reader.hpp"

#include "talus/grid/grid.hpp"
#include "talus/linalg/linear_solver.hpp"
#include "talus/material/plastic_material.hpp"
#include "talus/scene/memory_estimate.hpp"

#include "validator.hpp"
#include "yaml_checks.hpp"

#include <cerrno>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace talus {
namespace detail {

// --- Map -------------------------------------------------------------------------------------

Map::Map(const Validator& v, Item self, const std::vector<std::string>& allowed)
    : v_(v), self_(std::move(self)) {
  const YAML::Node& n = self_.node;
  if (!n.IsMap())
    v_.fail(self_, "expected a map of keys (" + join(allowed) + "), got " + describe(n));
  for (auto it = n.begin(); it != n.end(); ++it) {
    // Copies: the iterator hands out a temporary pair, so references into it would dangle.
    const YAML::Node k = it->first;
    const YAML::Node value = it->second;
    const YAML::Mark key_mark = k.Mark();
    if (!k.IsScalar())
      v_.fail(Item{k, key_mark, self_.path}, "a key must be a plain name, got " + describe(k));
    const std::string name = k.Scalar();
    const std::string path = child_path(self_.path, name);
    Item key_item{k, key_mark, path};
    if (std::find(allowed.begin(), allowed.end(), name) == allowed.end()) {
      std::string what =
          "unknown key '" + shown(name) + "' (allowed keys here: " + join(allowed) + ")";
      const std::string guess = closest_match(name, allowed);
      if (!guess.empty())
        what += "; did you mean '" + guess + "'?";
      v_.fail(key_item, what);
    }
    if (const Entry* first = find(name)) {
      const SourceLocation where = v_.locate(first->key);
      v_.fail(key_item, "key '" + name + "' is given twice (first at line " +
                            std::to_string(where.line) + ")");
    }
    entries_.push_back(Entry{name, key_item, Item{value, mark_or(value, key_mark), path}});
    v_.note_location(entries_.back().value);
  }
}

// --- the whole tree ------------------------------------------------------------------------

/// More values than any case file has, even with long lists of polygon vertices; the bound stops
/// aliases that repeat a list of lists ("billion laughs") from costing exponential time.
constexpr std::size_t kMaxValues = 1000000;

void Validator::check_tree(const YAML::Node& root) const {
  std::size_t count = 0;
  check_node(Item{root, root.Mark(), ""}, 0, count);
}

void Validator::check_node(const Item& it, int depth, std::size_t& count) const {
  if (depth > kMaxNesting)
    fail(it, fmt::format("the maps and lists nest more than {} levels deep here (a case file "
                         "needs fewer than 10)",
                         kMaxNesting));
  if (++count > kMaxValues)
    fail(it, fmt::format("the case holds more than {} values (are YAML aliases repeating a "
                         "list?)",
                         kMaxValues));
  const YAML::Node& n = it.node;
  const std::string& tag = n.Tag();
  // yaml-cpp gives an untagged plain value the tag "?" and an untagged quoted one "!".
  if (!tag.empty() && tag != "?" && tag != "!")
    fail(it, "YAML tags are not part of the case format (this value is tagged '" + shown(tag) +
                 "'); write the value without the tag");
  if (n.IsScalar() && tag == "!" && origin(it.mark, it.path) == nullptr &&
      quote_unterminated(text_, it.mark))
    fail(it, unterminated_quote_message(text_, it.mark));
  if (n.IsSequence()) {
    for (std::size_t i = 0; i < n.size(); ++i)
      check_node(Item{n[i], mark_or(n[i], it.mark), child_path(it.path, i)}, depth + 1, count);
  } else if (n.IsMap()) {
    for (auto entry = n.begin(); entry != n.end(); ++entry) {
      const YAML::Node key = entry->first;
      const YAML::Node value = entry->second;
      const std::string name = key.IsScalar() ? key.Scalar() : std::string("?");
      const std::string path = child_path(it.path, name);
      check_node(Item{key, key.Mark(), path}, depth + 1, count);
      check_node(Item{value, mark_or(value, key.Mark()), path}, depth + 1, count);
    }
  }
}

Item Map::required(const std::string& key) const {
  if (const Entry* e = find(key))
    return e->value;
  v_.fail(self_, "missing required key '" + key + "'");
}

// --- sections --------------------------------------------------------------------------------

std::string Validator::case_name(const Item& it) const {
  std::string s = name(it);
  if (s == "." || s == ".." || s.find('/') != std::string::npos ||
      s.find('\\') != std::string::npos)
    fail(it, "the case name '" + s +
                 "' must be usable as a directory name (no '/' or '\\', not '.' or '..')");
  return s;
}

AnalysisType Validator::analysis(const Item& it) const {
  return choice(it, analysis_choices());
}

int Validator::dimension(const Item& it) const {
  const Index d = integer(it);
  if (d != 2 && d != 3)
    fail(it, "must be 2 (plane strain) or 3 (got " + std::to_string(d) + ")");
  return static_cast<int>(d);
}

Geometry Validator::geometry(const Item& it) const {
  if (dimension_ == 3)
    fail(it, "geometry applies to a 2D case (plane_strain or axisymmetric); a 3D case is "
             "neither: remove the key");
  return choice(it, geometry_choices());
}

GridSpec Validator::grid(const Item& it) const {
  const Map m(*this, it, {"origin", "extent", "cell_size"});
  GridSpec g;
  g.dimension = dimension_;
  g.where = locate(m.self());
  if (m.has("origin"))
    g.origin = point(m["origin"]);
  const Item extent = m.required("extent");
  g.extent = point(extent);
  for (int d = 0; d < dimension_; ++d)
    if (!(g.extent[d] > 0))
      fail(extent, "every component must be > 0 (got " + vec(g.extent, dimension_) + ")");
  const Item cell = m.required("cell_size");
  g.cell_size = positive(cell);
  for (int d = 0; d < dimension_; ++d)
    if (!std::isfinite(g.origin[d] + g.extent[d]))
      fail(extent, "origin + extent overflows the double-precision range (the grid would end at "
                   "infinity)");
  for (int d = 0; d < dimension_; ++d) {
    const double cells = g.extent[d] / g.cell_size;
    // Beyond 2^53 cells consecutive counts are no longer distinct doubles (and no index type
    // holds the node count); the memory estimate refuses far smaller grids anyway.
    if (!std::isfinite(cells) || cells > 9.0e15)
      fail(cell, fmt::format("the grid extent in {} ({} m) divided by the cell size ({} m) is {} "
                             "cells, more than can be counted",
                             "xyz"[d], num(g.extent[d]), num(g.cell_size), num(cells)));
    const double whole = std::round(cells);
    if (whole < 1 || std::abs(cells - whole) > 1e-9 * cells)
      fail(cell, fmt::format("the grid extent in {} ({} m) is not a whole number of cells of "
                             "size {} m ({} / {} = {})",
                             "xyz"[d], num(g.extent[d]), num(g.cell_size), num(g.extent[d]),
                             num(g.cell_size), num(cells)));
  }
  // Nodes are numbered on the lattice (ghost layers included) with 64-bit integers; storage
  // follows the material, so a huge grid with a small body would otherwise be fine.
  double nodes = 1;
  for (int d = 0; d < dimension_; ++d)
    nodes *= std::round(g.extent[d] / g.cell_size) + 3;
  if (nodes > kMaxGridNodes)
    fail(cell, fmt::format("the grid has {} nodes (ghost layers included), more than Talus can "
                           "number ({}); use a coarser grid.cell_size or a smaller grid.extent",
                           num(nodes), num(kMaxGridNodes)));
  return g;
}

CaseSpec Validator::read(const YAML::Node& root) const {
  const Item top_item{root, root.Mark(), ""};
  if (root.IsNull() || !root.IsDefined())
    fail(top_item, "the case file is empty");
  if (!root.IsMap())
    fail(top_item, "a case file must be a map of keys (name:, grid:, ...), got " + describe(root));
  const Map top(*this, top_item,
                {"name",
                 "analysis",
                 "dimension",
                 "geometry",
                 "grid",
                 "materials",
                 "bodies",
                 "gravity",
                 "boundaries",
                 "point_loads",
                 "tractions",
                 "prescribed",
                 "time",
                 "output",
                 "probes",
                 "solver",
                 "strength_reduction",
                 "stages",
                 "silence_warnings",
                 "water"});
  CaseSpec spec;
  spec.name = case_name(top.required("name"));
  if (top.has("analysis") && !top.present("stages"))
    spec.analysis = analysis(top["analysis"]);
  if (top.has("dimension"))
    spec.dimension = dimension(top["dimension"]);
  dimension_ = spec.dimension;
  if (top.has("geometry"))
    spec.geometry = geometry(top["geometry"]);
  axisymmetric_ = spec.geometry == Geometry::Axisymmetric;
  spec.grid = grid(top.required("grid"));
  if (top.has("gravity"))
    spec.gravity = point(top["gravity"]);
  spec.materials = materials(top.required("materials"), spec.gravity);
  spec.bodies = bodies(top.required("bodies"), spec);
  if (top.present("water"))
    spec.water = water(top["water"], spec);
  if (top.present("stages")) {
    for (const char* key : {"analysis", "time"})
      if (top.has(key))
        fail(top.key(key), std::string("with 'stages', each stage gives its own analysis and "
                                       "time; remove the top-level '") +
                               key + "'");
    spec.stages = stages(top["stages"], spec);
    spec.analysis = spec.stages.front().analysis;
    spec.time = spec.stages.front().time;
  } else {
    const Item time_item = top.required("time");
    spec.time = time(time_item);
    check_time_step(time_item, spec.analysis, spec.time, spec);
  }
  for (std::size_t k = 0; k < spec.materials.size(); ++k)
    if (spec.materials[k].saturated_density && !spec.water)
      fail(list(top["materials"])[k],
           "material '" + spec.materials[k].name +
               "' has a saturated weight (saturated_density or saturated_unit_weight) but the "
               "case has no water section, the phreatic surface below which it applies");
  check_consolidation(top, spec);
  if (top.present("boundaries"))
    spec.boundaries = boundaries(top["boundaries"], spec);
  if (top.present("point_loads"))
    spec.point_loads = point_loads(top["point_loads"], spec);
  if (top.present("tractions"))
    spec.tractions = tractions(top["tractions"], spec);
  if (top.present("prescribed"))
    spec.prescribed = prescribed(top["prescribed"], spec);
  const bool any_plastic = std::any_of(spec.materials.begin(), spec.materials.end(),
                                       [](const MaterialSpec& m) { return is_plastic(m.model); });
  spec.output = top.present("output") ? output(top["output"], any_plastic, spec.water.has_value())
                                      : default_output(any_plastic, spec.water.has_value());
  if (top.present("probes"))
    spec.probes = probes(top["probes"], spec.grid);
  if (top.present("solver"))
    spec.solver = solver(top["solver"], spec);
  if (top.present("solver") && !spec.solver.linear_solver.empty()) {
    LinearSolverOptions options;
    parse_linear_solver_kind(spec.solver.linear_solver, options.kind);
    if (make_linear_solver(options)->requires_symmetric()) {
      const auto refuse = [&](const std::string& why) {
        fail(Map(*this, top["solver"], solver_keys())["linear_solver"],
             "'" + spec.solver.linear_solver + "' needs a symmetric tangent, but " + why +
                 " (nonsymmetric tangent); use umfpack, klu, eigen_bicgstab or trilinos_gmres, "
                 "or leave linear_solver out");
      };
      if (spec.solver.f_bar)
        refuse("f_bar couples the points of a cell through their average volume change");
      for (const auto& material : spec.materials)
        if (nonsymmetric_tangent(material))
          refuse("material '" + material.name + "' has non-associated flow or softening");
      if (spec.water)
        refuse("the water's pressure gradient acts on the points' current volume");
    }
  }
  if (top.present("strength_reduction"))
    spec.strength_reduction = strength_reduction(top["strength_reduction"], spec);
  if (top.present("silence_warnings"))
    spec.silenced_warnings = silenced_warnings(top["silence_warnings"]);
  check_memory(top, spec);
  spec.locations = std::move(locations_);
  return spec;
}

// A consolidation case couples every point's pore pressure to its skeleton by Newton on the
// grid: it needs the water's unit weight, a permeability for every material (an impermeable
// layer is a small one) and quasi-static implicit stages.
void Validator::check_consolidation(const Map& top, const CaseSpec& spec) const {
  const std::vector<Item> items = list(top["materials"]);
  const auto first = [&](bool flows) {
    return static_cast<std::size_t>(
        std::find_if(spec.materials.begin(), spec.materials.end(),
                     [&](const MaterialSpec& m) { return m.flow.has_value() == flows; }) -
        spec.materials.begin());
  };
  const std::size_t with = first(true), without = first(false);
  if (with == spec.materials.size())
    return;
  const std::string name = spec.materials[with].name;
  if (!spec.water)
    fail(items[with], "material '" + name +
                          "' has a permeability (a consolidation case) but the "
                          "case has no water section, which gives the water's unit weight");
  if (without < spec.materials.size())
    fail(items[without], "material '" + spec.materials[without].name +
                             "' has no permeability, but material '" + name +
                             "' has one: in a consolidation case every material carries pore "
                             "water (give an impermeable layer a small permeability)");
  const auto refuse = [&](AnalysisType a, const Item& at) {
    if (a != AnalysisType::ImplicitQuasistatic)
      fail(at, "material '" + name +
                   "' has a permeability: consolidation is solved by the "
                   "quasi-static implicit analysis (Newton on displacement and pore pressure); "
                   "use analysis: implicit_quasistatic");
  };
  if (spec.stages.empty()) {
    refuse(spec.analysis, top.has("analysis") ? top["analysis"] : top.self());
  } else {
    const std::vector<Item> stages = list(top["stages"]);
    for (std::size_t k = 0; k < spec.stages.size(); ++k)
      refuse(spec.stages[k].analysis, stages[k]);
  }
}

std::vector<PlausibilityCheck> Validator::silenced_warnings(const Item& it) const {
  std::vector<PlausibilityCheck> out;
  for (const Item& item : list(it))
    out.push_back(choice(item, plausibility_check_choices()));
  return out;
}

// Nothing is allocated for a case before this estimate said it fits: a grid of 1e-9 m cells
// is refused here, in a millisecond, instead of failing in std::bad_alloc after gigabytes.
// The limit is the machine's total memory (MemTotal, or a lower cgroup limit): a case above it
// can never run here, whereas one above what is available right now may run once other jobs
// end, so that only gets a warning (talus run, talus check).
void Validator::check_memory(const Map& top, const CaseSpec& spec) const {
  const MemoryEstimate estimate = estimate_memory(spec);
  const MachineMemory machine = machine_memory();
  if (estimate.total_bytes <= machine.total_bytes)
    return;
  // A body's points per cell are named when one point per direction would make the case fit;
  // otherwise the cell size is what has to change.
  Item at = Map(*this, top["grid"], {"origin", "extent", "cell_size"})["cell_size"];
  if (estimate.driver_body >= 0 && estimate.points > 0) {
    const auto b = static_cast<std::size_t>(estimate.driver_body);
    const BodySpec& body = spec.bodies[b];
    const int n = body.refine ? std::max(body.refine->particles_per_cell, body.particles_per_cell)
                              : body.particles_per_cell;
    const double share = estimate.point_bytes * estimate.body_points[b] / estimate.points;
    const bool fewer_points_fit =
        estimate.total_bytes - share * (1.0 - 1.0 / std::pow(n, spec.dimension)) <=
        machine.total_bytes;
    const YAML::Node node = list(top["bodies"])[b].node;
    const std::string key = estimate.driver_key.substr(estimate.driver_key.find('.') + 1);
    if (fewer_points_fit && key == "particles_per_cell" && node["particles_per_cell"])
      at = Item{node["particles_per_cell"], node["particles_per_cell"].Mark(), estimate.driver_key};
    else if (fewer_points_fit && key == "refine.particles_per_cell" && node["refine"] &&
             node["refine"]["particles_per_cell"])
      at = Item{node["refine"]["particles_per_cell"], node["refine"]["particles_per_cell"].Mark(),
                estimate.driver_key};
  }
  fail(at,
       fmt::format("the memory estimate of the case is {}, more than this machine has ({}, {}); "
                   "use a coarser grid.cell_size or fewer particles_per_cell",
                   estimate.describe(), format_bytes(machine.total_bytes), machine.source));
}

} // namespace detail

using detail::AppliedOverride;
using detail::Validator;

CaseSpec read_case_text(const std::string& text, const std::string& label,
                        const std::vector<std::string>& overrides) {
  const auto at = [&](std::size_t offset) {
    const auto [line, column] = detail::line_column(text, offset);
    return SourceLocation{label, line, column, ""};
  };
  if (const std::optional<detail::TextProblem> problem = detail::check_raw_text(text)) {
    SourceLocation where = at(problem->offset);
    where.key_path = detail::enclosing_key_path(text, problem->offset);
    throw InputError(where, problem->what);
  }
  YAML::Node root;
  try {
    const std::vector<YAML::Node> documents = YAML::LoadAll(text);
    if (!documents.empty())
      root = documents.front();
    for (std::size_t i = 1; i < documents.size(); ++i)
      if (!documents[i].IsNull()) {
        const YAML::Mark m = documents[i].Mark();
        throw InputError(
            SourceLocation{label, m.is_null() ? 0 : m.line + 1, m.is_null() ? 0 : m.column + 1, ""},
            "a case file holds one YAML document, but a second one starts here");
      }
  } catch (const YAML::ParserException& e) {
    const YAML::Mark& m = e.mark;
    // A plain key may be at most 1024 characters long (YAML 1.2, 7.4.2); yaml-cpp then says
    // "illegal map value" past the end of the key.
    if (e.msg == "illegal map value" && !m.is_null() && m.column > 1024) {
      const std::size_t line_start = text.rfind('\n', static_cast<std::size_t>(m.pos));
      const std::size_t start = line_start == std::string::npos ? 0 : line_start + 1;
      const std::size_t key = text.find_first_not_of(" -", start);
      const auto [line, column] = detail::line_column(text, key);
      throw InputError(SourceLocation{label, line, column, ""},
                       fmt::format("this key, '{}', is {} characters long; YAML allows at most "
                                   "1024 for a key",
                                   detail::shown(text.substr(key, 200)),
                                   static_cast<std::size_t>(m.pos) - key));
    }
    // yaml-cpp says "bad file" when it stops at its depth limit (check_raw_text counts nesting
    // conservatively, so this is only a fallback).
    const std::string what = e.msg == "bad file"
                                 ? "the maps and lists nest deeper than the YAML parser allows"
                                 : "YAML syntax error: " + e.msg;
    throw InputError(
        SourceLocation{label, m.is_null() ? 0 : m.line + 1, m.is_null() ? 0 : m.column + 1, ""},
        what);
  }

  // A document that is not a map is reported as such before any override tries to go into it.
  if (!root.IsNull() && !root.IsMap())
    Validator(label, {}, text).read(root);
  // Tags and open quotes of the file are reported before an override could replace the value.
  Validator(label, {}, text).check_tree(root);
  std::vector<AppliedOverride> applied = detail::apply_overrides(root, overrides);

  const Validator validator(label, std::move(applied), text);
  validator.check_tree(root);
  CaseSpec spec = validator.read(root);
  spec.source_file = label;
  spec.source_text = text;
  spec.overrides = overrides;
  return spec;
}

CaseSpec read_case_file(const std::string& path, const std::vector<std::string>& overrides) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw InputError(SourceLocation{path, 0, 0, ""},
                     "cannot read case file '" + path + "': it is a directory");
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    const int err = errno;
    const std::string reason = std::filesystem::exists(path, ec)
                                   ? std::generic_category().message(err != 0 ? err : EACCES)
                                   : "no such file";
    throw InputError(SourceLocation{path, 0, 0, ""},
                     "cannot open case file '" + path + "': " + reason);
  }
  std::ostringstream content;
  content << in.rdbuf();
  if (in.bad())
    throw InputError(SourceLocation{path, 0, 0, ""},
                     "error while reading case file '" + path + "'");
  return read_case_text(content.str(), path, overrides);
}

} // namespace talus