// YAML case file -> validated CaseSpec. The schema and every rule enforced here are documented in
// docs/case-format.md; keep the two in step.
#include "talus/io/case_reader.hpp"

#include "talus/core/expression.hpp"
#include "talus/linalg/linear_solver.hpp"
#include "talus/material/plastic_material.hpp"

#include "talus/core/errors.hpp"
#include "yaml_support.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <system_error>
#include <utility>
#include <yaml-cpp/yaml.h>

namespace talus {
namespace {

using detail::AppliedOverride;
using detail::child_path;
using detail::closest_match;
using detail::join;

/// A computed number for a message: 10 significant digits hide round-off (0.2 - 0.25 prints as
/// -0.05). Values the user typed are quoted from the YAML text instead.
std::string num(double v) {
  return fmt::format("{:.10g}", v);
}
std::string vec(const Vec2& v) {
  return "[" + num(v.x()) + ", " + num(v.y()) + "]";
}

bool starts_with(const std::string& s, const std::string& prefix) {
  return s.size() >= prefix.size() && s.compare(0, prefix.size(), prefix) == 0;
}

/// True when `inner` is `outer` or lies below it ("a.b" and "a[0]" lie below "a").
bool within(const std::string& inner, const std::string& outer) {
  if (outer.empty())
    return true;
  return inner == outer || starts_with(inner, outer + ".") || starts_with(inner, outer + "[");
}

/// How a node looks, for "expected X, got Y" messages.
/// "stage 'name'" of the first explicit stage ("the analysis" without stages), or empty.
std::string explicit_stage(const CaseSpec& spec) {
  if (spec.stages.empty())
    return spec.analysis == AnalysisType::Explicit ? "the analysis" : "";
  for (const StageSpec& stage : spec.stages)
    if (stage.analysis == AnalysisType::Explicit)
      return "stage '" + stage.name + "'";
  return "";
}

bool any_implicit_stage(const CaseSpec& spec) {
  if (spec.stages.empty())
    return spec.analysis != AnalysisType::Explicit;
  return std::any_of(spec.stages.begin(), spec.stages.end(), [](const StageSpec& stage) {
    return stage.analysis != AnalysisType::Explicit;
  });
}

/// Whether a strength factor has anything to divide (c and tan(phi) of a frictional model).
bool has_reducible_material(const std::vector<MaterialSpec>& materials) {
  return std::any_of(materials.begin(), materials.end(), [](const MaterialSpec& mat) {
    return mat.model == MaterialModel::Tresca || mat.model == MaterialModel::MohrCoulomb ||
           mat.model == MaterialModel::DruckerPrager;
  });
}

std::string describe(const YAML::Node& n) {
  switch (n.Type()) {
  case YAML::NodeType::Null:
    return "an empty value";
  case YAML::NodeType::Scalar:
    if (n.Tag() == "!")
      return "the quoted string \"" + n.Scalar() + "\"";
    return "'" + n.Scalar() + "'";
  case YAML::NodeType::Sequence:
    return "a list";
  case YAML::NodeType::Map:
    return "a map";
  case YAML::NodeType::Undefined:
    break;
  }
  return "nothing";
}

/// A value in the case tree and where it came from.
struct Item {
  YAML::Node node;
  YAML::Mark mark; ///< of the value; of its key when the value is empty
  std::string path;
};

YAML::Mark mark_or(const YAML::Node& n, const YAML::Mark& fallback) {
  const YAML::Mark m = n.Mark();
  return (m.is_null() || n.IsNull()) ? fallback : m;
}

class Validator;

/// A YAML map whose keys were checked against the allowed set (unknown keys, duplicate keys).
class Map {
public:
  Map(const Validator& v, Item self, const std::vector<std::string>& allowed);

  bool has(const std::string& key) const { return find(key) != nullptr; }
  /// Present and not empty (`output:` with nothing after it counts as absent).
  bool present(const std::string& key) const {
    const Entry* e = find(key);
    return e != nullptr && !e->value.node.IsNull();
  }
  Item operator[](const std::string& key) const { return find(key)->value; }
  Item required(const std::string& key) const;
  /// The key itself (its location), for errors about the key rather than its value.
  Item key(const std::string& key) const { return find(key)->key; }
  const Item& self() const { return self_; }

private:
  struct Entry {
    std::string name;
    Item key;
    Item value;
  };
  const Entry* find(const std::string& key) const {
    for (const auto& e : entries_)
      if (e.name == key)
        return &e;
    return nullptr;
  }
  const Validator& v_;
  Item self_;
  std::vector<Entry> entries_;
};

class Validator {
public:
  Validator(std::string file, std::vector<AppliedOverride> overrides)
      : file_(std::move(file)), overrides_(std::move(overrides)) {}

  CaseSpec read(const YAML::Node& root) const;

  // --- locations and errors -------------------------------------------------------------------
  /// The --set override a value at `path` came from, if any. A node that was created by an
  /// override (no mark) on the way to its key also counts.
  const AppliedOverride* origin(const YAML::Mark& mark, const std::string& path) const {
    for (auto it = overrides_.rbegin(); it != overrides_.rend(); ++it) {
      if (within(path, it->path))
        return &*it;
      if (mark.is_null() && !path.empty() && within(it->path, path))
        return &*it;
    }
    return nullptr;
  }

  SourceLocation locate(const YAML::Mark& mark, const std::string& path) const {
    if (origin(mark, path) != nullptr)
      return SourceLocation{"--set", 0, 0, path};
    if (mark.is_null())
      return SourceLocation{file_, 0, 0, path};
    return SourceLocation{file_, mark.line + 1, mark.column + 1, path};
  }
  SourceLocation locate(const Item& it) const { return locate(it.mark, it.path); }

  [[noreturn]] void fail(const Item& at, const std::string& what) const {
    std::string message = what;
    if (const AppliedOverride* o = origin(at.mark, at.path))
      message += " (from --set " + o->text + ")";
    throw InputError(locate(at), message);
  }

  // --- typed values ---------------------------------------------------------------------------
  /// Any scalar, as text.
  std::string text(const Item& it) const {
    if (!it.node.IsScalar())
      fail(it, "expected a text value, got " + describe(it.node));
    return it.node.Scalar();
  }

  /// A name: non-empty text.
  std::string name(const Item& it) const {
    std::string s = text(it);
    if (s.empty())
      fail(it, "a name must not be empty");
    return s;
  }

  double number(const Item& it) const { return parse_number(it, "a number"); }

  /// A finite number; `expected` names the kind for "expected X, got Y".
  double parse_number(const Item& it, const std::string& expected) const {
    const YAML::Node& n = it.node;
    if (!n.IsScalar() || n.Tag() == "!" || n.Tag() == "tag:yaml.org,2002:str")
      fail(it, "expected " + expected + ", got " + describe(n));
    const std::string& s = n.Scalar();
    std::string lower;
    for (char c : s)
      lower += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (!lower.empty() && (lower[0] == '+' || lower[0] == '-'))
      lower.erase(0, 1);
    if (lower == ".inf" || lower == "inf" || lower == "infinity" || lower == ".nan" ||
        lower == "nan")
      fail(it, "must be a finite number (got " + s + "); NaN and infinity are not physical");
    const char* begin = s.data();
    const char* end = s.data() + s.size();
    if (begin != end && *begin == '+')
      ++begin;
    double v = 0;
    const auto [ptr, ec] = std::from_chars(begin, end, v);
    if (ec == std::errc::result_out_of_range)
      fail(it, "number " + s + " is out of the double-precision range");
    if (ec != std::errc() || ptr != end || begin == end)
      fail(it, "expected " + expected + ", got " + describe(n));
    if (!std::isfinite(v))
      fail(it, "must be a finite number (got " + s + ")");
    return v;
  }

  Index integer(const Item& it) const {
    const YAML::Node& n = it.node;
    const double v = parse_number(it, "an integer");
    if (v != std::floor(v))
      fail(it, "expected an integer, got " + describe(n));
    if (std::abs(v) > 9.0e15)
      fail(it, "integer " + n.Scalar() + " is out of range");
    return static_cast<Index>(v);
  }

  Vec2 vec2(const Item& it) const {
    const YAML::Node& n = it.node;
    if (!n.IsSequence())
      fail(it, "expected a 2-element list [x, y], got " + describe(n));
    if (n.size() != 2)
      fail(it, "expected a 2-element list [x, y], got a list of " + std::to_string(n.size()) +
                   " element" + (n.size() == 1 ? "" : "s"));
    Vec2 v;
    for (std::size_t i = 0; i < 2; ++i)
      v[static_cast<Eigen::Index>(i)] =
          number(Item{n[i], mark_or(n[i], it.mark), child_path(it.path, i)});
    return v;
  }

  /// True for text that is meant as a number, valid or not (1e5, -3, 1e400, .inf, .nan), as
  /// opposed to an expression such as 0.1*sin(x).
  static bool looks_numeric(const std::string& s) {
    std::string lower;
    for (char c : s)
      lower += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (!lower.empty() && (lower[0] == '+' || lower[0] == '-'))
      lower.erase(0, 1);
    if (lower == ".inf" || lower == "inf" || lower == "infinity" || lower == ".nan" ||
        lower == "nan")
      return true;
    char* end = nullptr;
    std::strtod(lower.c_str(), &end);
    return !lower.empty() && end == lower.c_str() + lower.size();
  }

  /// A 2-element list whose elements are numbers or expressions of the initial position
  /// (quoted text such as "0.01 * sin(pi / 50 * x)"); expressions are parsed here so a typo is
  /// reported with its location.
  void position_field(const Item& it, Vec2& values, std::array<std::string, 2>& expressions) const {
    const YAML::Node& n = it.node;
    if (!n.IsSequence() || n.size() != 2)
      fail(it, "expected a 2-element list [x, y] of numbers or expressions in x and y, got " +
                   describe(n));
    for (std::size_t i = 0; i < 2; ++i) {
      const Item element{n[i], mark_or(n[i], it.mark), child_path(it.path, i)};
      const bool quoted =
          element.node.IsScalar() &&
          (element.node.Tag() == "!" || element.node.Tag() == "tag:yaml.org,2002:str");
      if (!element.node.IsScalar())
        fail(element,
             "expected a number or an expression in x and y, got " + describe(element.node));
      if (!quoted && looks_numeric(element.node.Scalar())) {
        values[static_cast<Eigen::Index>(i)] = number(element); // reports 1e400, .nan, ...
        continue;
      }
      try {
        const PositionExpression check(element.node.Scalar());
        (void)check;
      } catch (const std::invalid_argument& e) {
        fail(element, e.what());
      }
      expressions[i] = element.node.Scalar();
      values[static_cast<Eigen::Index>(i)] = 0.0;
    }
  }

  std::vector<Item> list(const Item& it) const {
    const YAML::Node& n = it.node;
    if (!n.IsSequence())
      fail(it, "expected a list, got " + describe(n));
    std::vector<Item> items;
    for (std::size_t i = 0; i < n.size(); ++i)
      items.push_back(Item{n[i], mark_or(n[i], it.mark), child_path(it.path, i)});
    return items;
  }

  template <class E>
  E choice(const Item& it, const std::vector<std::pair<std::string, E>>& options) const {
    std::vector<std::string> names;
    for (const auto& [word, value] : options)
      names.push_back(word);
    if (!it.node.IsScalar())
      fail(it, "expected one of " + join(names) + ", got " + describe(it.node));
    const std::string& s = it.node.Scalar();
    for (const auto& [word, value] : options)
      if (word == s)
        return value;
    std::string what = "unknown value '" + s + "' (allowed: " + join(names) + ")";
    const std::string guess = closest_match(s, names);
    if (!guess.empty())
      what += "; did you mean '" + guess + "'?";
    fail(it, what);
  }

  /// true or false (YAML's plain booleans only: a switch spelled yes/on is more likely a typo).
  bool boolean(const Item& it) const {
    const YAML::Node& n = it.node;
    const bool quoted = n.Tag() == "!" || n.Tag() == "tag:yaml.org,2002:str";
    if (n.IsScalar() && !quoted && (n.Scalar() == "true" || n.Scalar() == "false"))
      return n.Scalar() == "true";
    fail(it, "expected true or false, got " + describe(n));
  }

  double positive(const Item& it) const {
    const double v = number(it);
    if (!(v > 0))
      fail(it, "must be > 0 (got " + it.node.Scalar() + ")");
    return v;
  }

private:
  std::string case_name(const Item& it) const;
  AnalysisType analysis(const Item& it) const;
  int dimension(const Item& it) const;
  GridSpec grid(const Item& it) const;
  std::vector<MaterialSpec> materials(const Item& it) const;
  std::vector<BodySpec> bodies(const Item& it, const CaseSpec& spec) const;
  void body_shape(const Map& m, BodySpec& b) const;
  void body_inside_grid(const Map& m, const BodySpec& b, const GridSpec& g) const;
  BoundarySpec boundaries(const Item& it) const;
  std::vector<PointLoadSpec> point_loads(const Item& it) const;
  std::vector<TractionSpec> tractions(const Item& it, const CaseSpec& spec) const;
  std::vector<PrescribedSpec> prescribed(const Item& it, const CaseSpec& spec) const;
  TimeSpec time(const Item& it) const;
  std::vector<StageSpec> stages(const Item& it, const CaseSpec& spec) const;
  void check_time_step(const Item& time_item, AnalysisType analysis, const TimeSpec& time,
                       const CaseSpec& spec) const;
  void check_explicit_time_step(const Item& time_item, const TimeSpec& time,
                                const CaseSpec& spec) const;
  OutputSpec output(const Item& it, bool any_plastic) const;
  std::vector<ProbeSpec> probes(const Item& it) const;
  SolverSpec solver(const Item& it, const CaseSpec& spec) const;
  StrengthReductionSpec strength_reduction(const Item& it, const CaseSpec& spec) const;
  void plastic_parameters(const Map& m, const Item& model_item, MaterialSpec& s) const;
  static std::vector<std::string> solver_keys();
  BodySpec::Placement placement(const Item& it) const;
  BodySpec::InitialStress initial_stress(const Item& it, const BodySpec& b,
                                         const CaseSpec& spec) const;
  SplitSpec split(const Item& it) const;
  BodySpec::Refine refine(const Item& it) const;

  /// Remembers names of one kind and rejects a repeat.
  class UniqueNames {
  public:
    UniqueNames(const Validator& v, std::string kind) : v_(v), kind_(std::move(kind)) {}
    void add(const std::string& name, const Item& where, const std::string& owner) {
      const auto [it, inserted] = seen_.emplace(name, owner);
      if (!inserted)
        v_.fail(where,
                "duplicate " + kind_ + " name '" + name + "' (already used by " + it->second + ")");
    }

  private:
    const Validator& v_;
    std::string kind_;
    std::map<std::string, std::string> seen_;
  };

  std::string file_;
  std::vector<AppliedOverride> overrides_;
};

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
      std::string what = "unknown key '" + name + "' (allowed keys here: " + join(allowed) + ")";
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
  return choice<AnalysisType>(it, {{"explicit", AnalysisType::Explicit},
                                   {"implicit_quasistatic", AnalysisType::ImplicitQuasistatic},
                                   {"implicit_dynamic", AnalysisType::ImplicitDynamic}});
}

int Validator::dimension(const Item& it) const {
  const Index d = integer(it);
  if (d != 2)
    fail(it, "only 2 (plane strain) is supported (got " + std::to_string(d) + ")");
  return 2;
}

GridSpec Validator::grid(const Item& it) const {
  const Map m(*this, it, {"origin", "extent", "cell_size"});
  GridSpec g;
  g.where = locate(m.self());
  if (m.has("origin"))
    g.origin = vec2(m["origin"]);
  const Item extent = m.required("extent");
  g.extent = vec2(extent);
  if (!(g.extent.x() > 0 && g.extent.y() > 0))
    fail(extent, "both components must be > 0 (got " + vec(g.extent) + ")");
  const Item cell = m.required("cell_size");
  g.cell_size = positive(cell);
  for (int d = 0; d < 2; ++d) {
    const double cells = g.extent[d] / g.cell_size;
    const double whole = std::round(cells);
    if (whole < 1 || std::abs(cells - whole) > 1e-9 * cells)
      fail(cell, fmt::format("the grid extent in {} ({} m) is not a whole number of cells of "
                             "size {} m ({} / {} = {})",
                             d == 0 ? "x" : "y", num(g.extent[d]), num(g.cell_size),
                             num(g.extent[d]), num(g.cell_size), num(cells)));
  }
  return g;
}

std::vector<MaterialSpec> Validator::materials(const Item& it) const {
  const std::vector<Item> items = list(it);
  if (items.empty())
    fail(it, "list at least one material");
  std::vector<MaterialSpec> out;
  UniqueNames names(*this, "material");
  for (const Item& item : items) {
    const Map m(*this, item,
                {"name", "model", "density", "youngs_modulus", "poisson_ratio", "kinematics",
                 "yield_stress", "hardening_modulus", "cohesion", "friction_angle",
                 "dilation_angle", "residual"});
    MaterialSpec s;
    s.where = locate(m.self());
    const Item name_item = m.required("name");
    s.name = name(name_item);
    names.add(s.name, name_item, item.path);
    const Item model_item = m.required("model");
    s.model = choice<MaterialModel>(model_item, {{"linear_elastic", MaterialModel::LinearElastic},
                                                 {"neo_hookean", MaterialModel::NeoHookean},
                                                 {"hencky", MaterialModel::Hencky},
                                                 {"von_mises", MaterialModel::VonMises},
                                                 {"tresca", MaterialModel::Tresca},
                                                 {"mohr_coulomb", MaterialModel::MohrCoulomb},
                                                 {"drucker_prager", MaterialModel::DruckerPrager}});
    s.density = positive(m.required("density"));
    s.youngs_modulus = positive(m.required("youngs_modulus"));
    const Item nu = m.required("poisson_ratio");
    s.poisson_ratio = number(nu);
    if (!(s.poisson_ratio > -1 && s.poisson_ratio < 0.5))
      fail(nu, "must be in the open interval (-1, 0.5) (got " + nu.node.Scalar() + ")");
    plastic_parameters(m, model_item, s);
    out.push_back(std::move(s));
  }
  return out;
}

BodySpec::Placement Validator::placement(const Item& it) const {
  const Map m(*this, it, {"offset", "jitter", "seed"});
  BodySpec::Placement p;
  if (m.has("offset")) {
    p.offset = vec2(m["offset"]);
    // Half a spacing or more would move a point into its neighbour's lattice cell.
    if (p.offset.cwiseAbs().maxCoeff() >= 0.5)
      fail(m["offset"], "each component must lie in the open interval (-0.5, 0.5) (a fraction "
                        "of the point spacing)");
  }
  if (m.has("jitter")) {
    p.jitter = number(m["jitter"]);
    if (p.jitter < 0 || p.jitter >= 0.5)
      fail(m["jitter"], "must lie in [0, 0.5) (a fraction of the point spacing, so that every "
                        "point stays in its own lattice cell)");
  }
  if (m.has("seed")) {
    const Index seed = integer(m["seed"]);
    if (seed < 0 || seed > 4294967295)
      fail(m["seed"], "must be an integer from 0 to 4294967295");
    p.seed = static_cast<unsigned>(seed);
  }
  return p;
}

BodySpec::InitialStress Validator::initial_stress(const Item& it, const BodySpec& b,
                                                  const CaseSpec& spec) const {
  const MaterialSpec& material = spec.materials[static_cast<std::size_t>(b.material_index)];
  if (!is_plastic(material.model))
    fail(it, "an initial stress needs a model with an elastic strain state (von_mises, tresca, "
             "mohr_coulomb, drucker_prager); material '" +
                 material.name + "' is elastic, its stress follows from F alone");
  const Map m(*this, it, {"type", "surface", "k0", "stress"});
  BodySpec::InitialStress s;
  using Kind = BodySpec::InitialStress::Kind;
  s.kind = choice<Kind>(m.required("type"),
                        {{"geostatic", Kind::Geostatic}, {"uniform", Kind::Uniform}});
  for (const char* key : {"surface", "k0", "stress"}) {
    const bool geostatic_key = std::string(key) != "stress";
    if (m.has(key) && geostatic_key != (s.kind == Kind::Geostatic))
      fail(m.key(key), std::string("'") + key + "' does not apply to initial stress type '" +
                           m["type"].node.Scalar() + "'");
  }
  if (s.kind == Kind::Uniform) {
    const Item stress = m.required("stress");
    const std::vector<Item> values = list(stress);
    if (values.size() != 4)
      fail(stress, "give four stresses [sigma_xx, sigma_yy, sigma_xy, sigma_zz] in Pa");
    for (std::size_t k = 0; k < 4; ++k)
      s.stress[k] = number(values[k]);
    return s;
  }
  if (spec.gravity.norm() == 0.0 || spec.gravity.x() != 0.0 || spec.gravity.y() > 0.0)
    fail(m.self(), "a geostatic initial stress needs gravity along -y (gravity: [0, -g])");
  // Default surface: the body's top.
  switch (b.shape) {
  case BodyShape::Rectangle:
    s.surface = b.max.y();
    break;
  case BodyShape::Disc:
    s.surface = b.centre.y() + b.radius;
    break;
  case BodyShape::Polygon:
    s.surface = -std::numeric_limits<double>::infinity();
    for (const Vec2& v : b.vertices)
      s.surface = std::max(s.surface, v.y());
    break;
  }
  if (m.has("surface"))
    s.surface = number(m["surface"]);
  if (m.has("k0")) {
    const Item k0 = m["k0"];
    s.k0 = number(k0);
    if (!(*s.k0 > 0.0))
      fail(k0, "must be positive (got " + k0.node.Scalar() + ")");
  }
  return s;
}

std::vector<std::string> Validator::solver_keys() {
  return {"shape",
          "scheme",
          "transfer",
          "flip",
          "linear_solver",
          "newton_tolerance",
          "max_newton_iterations",
          "easy_newton_iterations",
          "ghost_penalty",
          "f_bar"};
}

void Validator::plastic_parameters(const Map& m, const Item& model_item, MaterialSpec& s) const {
  // The keys each model takes beyond the elastic ones; any other is refused by name.
  const std::vector<std::string> frictional = {"kinematics", "cohesion", "friction_angle",
                                               "dilation_angle", "residual"};
  std::vector<std::string> takes;
  switch (s.model) {
  case MaterialModel::VonMises:
    takes = {"kinematics", "yield_stress", "hardening_modulus"};
    break;
  case MaterialModel::Tresca:
    takes = {"kinematics", "cohesion"};
    break;
  case MaterialModel::MohrCoulomb:
  case MaterialModel::DruckerPrager:
    takes = frictional;
    break;
  default:
    break;
  }
  for (const char* key : {"kinematics", "yield_stress", "hardening_modulus", "cohesion",
                          "friction_angle", "dilation_angle", "residual"})
    if (m.has(key) && std::find(takes.begin(), takes.end(), key) == takes.end())
      fail(m.key(key), std::string("'") + key + "' does not apply to model '" +
                           model_item.node.Scalar() + "'" +
                           (takes.empty() ? std::string(" (an elastic model)")
                                          : " (it takes: " + join(takes) + ")"));
  if (takes.empty())
    return;
  if (m.has("kinematics"))
    s.small_strain =
        choice<bool>(m["kinematics"], {{"finite_strain", false}, {"small_strain", true}});
  if (s.model == MaterialModel::VonMises) {
    s.yield_stress = positive(m.required("yield_stress"));
    if (m.has("hardening_modulus"))
      s.hardening_modulus = number(m["hardening_modulus"]);
  } else {
    s.cohesion = number(m.required("cohesion"));
  }
  if (s.model == MaterialModel::MohrCoulomb || s.model == MaterialModel::DruckerPrager) {
    s.friction_angle = number(m.required("friction_angle"));
    if (m.has("dilation_angle"))
      s.dilation_angle = number(m["dilation_angle"]);
    if (m.present("residual")) {
      const Map r(*this, m["residual"], {"cohesion", "friction_angle", "plastic_strain"});
      s.residual =
          ResidualStrengthSpec{number(r.required("cohesion")), number(r.required("friction_angle")),
                               number(r.required("plastic_strain"))};
    }
  }
  // The model checks its own parameters (ranges, psi <= phi, ...); report at the key it names.
  try {
    make_plastic_model(s);
  } catch (const InputError& e) {
    std::string key = e.where().key_path;
    if (key == "residual.kappa")
      key = "residual.plastic_strain";
    Item at = m.self();
    if (key.rfind("residual.", 0) == 0 && m.present("residual")) {
      const Map r(*this, m["residual"], {"cohesion", "friction_angle", "plastic_strain"});
      const std::string sub = key.substr(9);
      if (r.has(sub))
        at = r[sub];
    } else if (m.has(key)) {
      at = m[key];
    }
    fail(at, e.detail());
  }
}

SplitSpec Validator::split(const Item& it) const {
  const Map m(*this, it, {"alpha", "beta", "gamma", "max_generations", "min_size"});
  SplitSpec s;
  if (m.has("alpha")) {
    const Item alpha = m["alpha"];
    s.alpha = number(alpha);
    if (!(s.alpha > 1.0))
      fail(alpha, "must be > 1: a stretch limit (got " + alpha.node.Scalar() + ")");
  }
  if (m.has("beta")) {
    const Item beta = m["beta"];
    s.beta = number(beta);
    if (!(s.beta > 0.0 && s.beta < 1.0))
      fail(beta, "must be in the open interval (0, 1): a compression limit (got " +
                     beta.node.Scalar() + ")");
  }
  if (m.has("gamma"))
    s.gamma = positive(m["gamma"]);
  if (m.has("max_generations")) {
    const Item gen = m["max_generations"];
    const Index n = integer(gen);
    // 2^30 descendants of one point is far beyond any memory; the cap keeps the count in int.
    if (n < 0 || n > 30)
      fail(gen, "must be an integer from 0 to 30 (got " + gen.node.Scalar() + ")");
    s.max_generations = static_cast<int>(n);
  }
  if (m.has("min_size")) {
    const Item size = m["min_size"];
    s.min_size = number(size);
    if (!(s.min_size >= 0.0))
      fail(size, "must be >= 0 m (got " + size.node.Scalar() + ")");
  }
  return s;
}

BodySpec::Refine Validator::refine(const Item& it) const {
  const Map m(*this, it, {"particles_per_cell", "boxes"});
  BodySpec::Refine r;
  const Item ppc = m.required("particles_per_cell");
  const Index n = integer(ppc);
  if (n < 1 || n > 16)
    fail(ppc, "must be an integer from 1 to 16 (got " + ppc.node.Scalar() + ")");
  r.particles_per_cell = static_cast<int>(n);
  for (const Item& box : list(m.required("boxes"))) {
    const std::vector<Item> values = list(box);
    if (values.size() != 4)
      fail(box, "give a box as [x_min, y_min, x_max, y_max] in m");
    std::array<double, 4> b{};
    for (std::size_t k = 0; k < 4; ++k)
      b[k] = number(values[k]);
    if (!(b[2] > b[0] && b[3] > b[1]))
      fail(box, "a box needs x_max > x_min and y_max > y_min");
    r.boxes.push_back(b);
  }
  return r;
}

std::vector<BodySpec> Validator::bodies(const Item& it, const CaseSpec& spec) const {
  const std::vector<Item> items = list(it);
  if (items.empty())
    fail(it, "list at least one body");
  std::vector<std::string> material_names;
  for (const auto& mat : spec.materials)
    material_names.push_back(mat.name);

  std::vector<BodySpec> out;
  UniqueNames names(*this, "body");
  for (const Item& item : items) {
    const Map m(*this, item,
                {"name", "material", "shape", "centre", "radius", "min", "max", "vertices",
                 "particles_per_cell", "velocity", "angular_velocity", "initial_stress", "split",
                 "placement", "refine"});
    BodySpec b;
    b.where = locate(m.self());
    const Item name_item = m.required("name");
    b.name = name(name_item);
    names.add(b.name, name_item, item.path);

    const Item material = m.required("material");
    b.material = name(material);
    const auto found = std::find(material_names.begin(), material_names.end(), b.material);
    if (found == material_names.end()) {
      std::string what =
          "unknown material '" + b.material + "' (defined materials: " + join(material_names) + ")";
      const std::string guess = closest_match(b.material, material_names);
      if (!guess.empty())
        what += "; did you mean '" + guess + "'?";
      fail(material, what);
    }
    b.material_index = static_cast<int>(found - material_names.begin());

    body_shape(m, b);

    if (m.has("particles_per_cell")) {
      const Item ppc = m["particles_per_cell"];
      const Index n = integer(ppc);
      if (n < 1 || n > 16)
        fail(ppc, "must be an integer from 1 to 16 (got " + ppc.node.Scalar() + ")");
      b.particles_per_cell = static_cast<int>(n);
    }
    if (m.has("velocity"))
      position_field(m["velocity"], b.velocity, b.velocity_expression);
    if (m.has("angular_velocity"))
      b.angular_velocity = number(m["angular_velocity"]);
    if (m.present("placement"))
      b.placement = placement(m["placement"]);

    body_inside_grid(m, b, spec.grid);
    if (m.present("initial_stress"))
      b.initial_stress = initial_stress(m["initial_stress"], b, spec);
    if (m.present("split"))
      b.split = split(m["split"]);
    if (m.present("refine"))
      b.refine = refine(m["refine"]);
    out.push_back(std::move(b));
  }
  return out;
}

double cross(const Vec2& a, const Vec2& b) {
  return a.x() * b.y() - a.y() * b.x();
}

int orientation(const Vec2& a, const Vec2& b, const Vec2& c) {
  const double o = cross(b - a, c - a);
  return (o > 0) - (o < 0);
}

bool on_segment(const Vec2& a, const Vec2& b, const Vec2& p) {
  return std::min(a.x(), b.x()) <= p.x() && p.x() <= std::max(a.x(), b.x()) &&
         std::min(a.y(), b.y()) <= p.y() && p.y() <= std::max(a.y(), b.y());
}

/// Closed segments [p1, p2] and [q1, q2] share at least one point.
bool segments_touch(const Vec2& p1, const Vec2& p2, const Vec2& q1, const Vec2& q2) {
  const int o1 = orientation(p1, p2, q1), o2 = orientation(p1, p2, q2);
  const int o3 = orientation(q1, q2, p1), o4 = orientation(q1, q2, p2);
  if (o1 != o2 && o3 != o4)
    return true;
  return (o1 == 0 && on_segment(p1, p2, q1)) || (o2 == 0 && on_segment(p1, p2, q2)) ||
         (o3 == 0 && on_segment(q1, q2, p1)) || (o4 == 0 && on_segment(q1, q2, p2));
}

void Validator::body_shape(const Map& m, BodySpec& b) const {
  b.shape = choice<BodyShape>(m.required("shape"), {{"rectangle", BodyShape::Rectangle},
                                                    {"disc", BodyShape::Disc},
                                                    {"polygon", BodyShape::Polygon}});
  struct ShapeKeys {
    BodyShape shape;
    const char* name;
    std::vector<std::string> keys;
  };
  static const std::array<ShapeKeys, 3> shapes{{{BodyShape::Rectangle, "rectangle", {"min", "max"}},
                                                {BodyShape::Disc, "disc", {"centre", "radius"}},
                                                {BodyShape::Polygon, "polygon", {"vertices"}}}};
  const ShapeKeys* mine = nullptr;
  for (const auto& s : shapes)
    if (s.shape == b.shape)
      mine = &s;
  for (const auto& s : shapes) {
    if (s.shape == b.shape)
      continue;
    for (const auto& key : s.keys)
      if (m.has(key))
        fail(m.key(key), "key '" + key + "' does not apply to shape " + mine->name + " (" +
                             mine->name + " takes " + join(mine->keys) + ")");
  }

  switch (b.shape) {
  case BodyShape::Rectangle: {
    b.min = vec2(m.required("min"));
    const Item max = m.required("max");
    b.max = vec2(max);
    if (!(b.max.x() > b.min.x() && b.max.y() > b.min.y()))
      fail(max, "max must be greater than min in both x and y (min " + vec(b.min) + ", max " +
                    vec(b.max) + ")");
    break;
  }
  case BodyShape::Disc:
    b.centre = vec2(m.required("centre"));
    b.radius = positive(m.required("radius"));
    break;
  case BodyShape::Polygon: {
    const Item vertices = m.required("vertices");
    const std::vector<Item> items = list(vertices);
    if (items.size() < 3)
      fail(vertices,
           "a polygon needs at least 3 vertices (got " + std::to_string(items.size()) + ")");
    for (const Item& v : items)
      b.vertices.push_back(vec2(v));
    const std::size_t n = b.vertices.size();
    double area2 = 0;
    Vec2 lo = b.vertices[0], hi = b.vertices[0];
    for (std::size_t i = 0; i < n; ++i) {
      area2 += cross(b.vertices[i], b.vertices[(i + 1) % n]);
      lo = lo.cwiseMin(b.vertices[i]);
      hi = hi.cwiseMax(b.vertices[i]);
    }
    if (std::abs(area2) <= 1e-12 * (hi - lo).squaredNorm())
      fail(vertices, "the polygon has zero area (are its vertices collinear or repeated?)");
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = i + 2; j < n; ++j) {
        if (i == 0 && j == n - 1)
          continue; // adjacent through the closing edge
        if (segments_touch(b.vertices[i], b.vertices[i + 1], b.vertices[j],
                           b.vertices[(j + 1) % n]))
          fail(vertices, fmt::format("the polygon is not simple: edge {}-{} touches edge {}-{} "
                                     "(vertices are numbered from 0)",
                                     i, i + 1, j, (j + 1) % n));
      }
    break;
  }
  }
}

void Validator::body_inside_grid(const Map& m, const BodySpec& b, const GridSpec& g) const {
  const Vec2 lo = g.origin, hi = g.origin + g.extent;
  const double tol = 1e-12 * (g.origin.cwiseAbs().maxCoeff() + g.extent.maxCoeff());
  const auto inside = [&](const Vec2& p) {
    return p.x() >= lo.x() - tol && p.x() <= hi.x() + tol && p.y() >= lo.y() - tol &&
           p.y() <= hi.y() + tol;
  };
  std::string grid_box = fmt::format("the grid covers x in [{}, {}], y in [{}, {}]", num(lo.x()),
                                     num(hi.x()), num(lo.y()), num(hi.y()));
  for (const char* key : {"grid.origin", "grid.extent"})
    if (const AppliedOverride* o = origin(YAML::Mark::null_mark(), key)) {
      grid_box += " (the grid was changed by --set " + o->text + ")";
      break;
    }
  const std::string head = "body '" + b.name + "' extends outside the grid: ";
  switch (b.shape) {
  case BodyShape::Rectangle:
    if (!inside(b.min))
      fail(m["min"], head + "min " + vec(b.min) + " lies outside; " + grid_box);
    if (!inside(b.max))
      fail(m["max"], head + "max " + vec(b.max) + " lies outside; " + grid_box);
    break;
  case BodyShape::Disc: {
    if (!inside(b.centre))
      fail(m["centre"], head + "centre " + vec(b.centre) + " lies outside; " + grid_box);
    const Vec2 r(b.radius, b.radius);
    const Vec2 dlo = b.centre - r, dhi = b.centre + r;
    if (!inside(dlo) || !inside(dhi))
      fail(m["radius"], head +
                            fmt::format("the disc covers x in [{}, {}], y in [{}, {}]; ",
                                        num(dlo.x()), num(dhi.x()), num(dlo.y()), num(dhi.y())) +
                            grid_box);
    break;
  }
  case BodyShape::Polygon: {
    const Item vertices = m["vertices"];
    for (std::size_t i = 0; i < b.vertices.size(); ++i)
      if (!inside(b.vertices[i]))
        fail(Item{vertices.node[i], mark_or(vertices.node[i], vertices.mark),
                  child_path(vertices.path, i)},
             head + "vertex " + vec(b.vertices[i]) + " lies outside; " + grid_box);
    break;
  }
  }
}

BoundarySpec Validator::boundaries(const Item& it) const {
  const Map m(*this, it, {"x_min", "x_max", "y_min", "y_max"});
  const std::vector<std::pair<std::string, FaceCondition>> options{
      {"free", FaceCondition::Free},
      {"fixed", FaceCondition::Fixed},
      {"roller", FaceCondition::Roller}};
  BoundarySpec b;
  const std::pair<const char*, FaceCondition*> faces[] = {
      {"x_min", &b.x_min}, {"x_max", &b.x_max}, {"y_min", &b.y_min}, {"y_max", &b.y_max}};
  for (const auto& [key, field] : faces)
    if (m.has(key))
      *field = choice(m[key], options);
  return b;
}

std::vector<PointLoadSpec> Validator::point_loads(const Item& it) const {
  std::vector<PointLoadSpec> out;
  UniqueNames names(*this, "point load");
  const std::vector<Item> items = list(it);
  for (std::size_t i = 0; i < items.size(); ++i) {
    const Map m(*this, items[i], {"name", "point", "force"});
    PointLoadSpec p;
    p.where = locate(m.self());
    if (m.has("name")) {
      p.name = name(m["name"]);
      names.add(p.name, m["name"], items[i].path);
    } else {
      p.name = "load" + std::to_string(i);
      names.add(p.name, m.self(), items[i].path + " (default name)");
    }
    p.point = vec2(m.required("point"));
    p.force = vec2(m.required("force"));
    out.push_back(std::move(p));
  }
  return out;
}

std::vector<TractionSpec> Validator::tractions(const Item& it, const CaseSpec& spec) const {
  std::vector<TractionSpec> out;
  std::vector<std::string> body_names;
  for (const auto& b : spec.bodies)
    body_names.push_back(b.name);
  for (const Item& item : list(it)) {
    const Map m(*this, item, {"body", "side", "traction", "constant"});
    TractionSpec t;
    t.where = locate(m.self());
    const Item body = m.required("body");
    t.body = name(body);
    const auto found = std::find(body_names.begin(), body_names.end(), t.body);
    if (found == body_names.end()) {
      std::string what = "unknown body '" + t.body + "' (defined bodies: " + join(body_names) + ")";
      const std::string guess = closest_match(t.body, body_names);
      if (!guess.empty())
        what += "; did you mean '" + guess + "'?";
      fail(body, what);
    }
    t.body_index = static_cast<int>(found - body_names.begin());
    const BodyShape shape = spec.bodies[static_cast<std::size_t>(t.body_index)].shape;
    if (shape != BodyShape::Rectangle)
      fail(body, "a traction needs a rectangle body, but body '" + t.body + "' is a " +
                     (shape == BodyShape::Disc ? "disc" : "polygon"));
    t.side = choice<Side>(m.required("side"), {{"left", Side::Left},
                                               {"right", Side::Right},
                                               {"bottom", Side::Bottom},
                                               {"top", Side::Top}});
    t.traction = vec2(m.required("traction"));
    if (m.has("constant"))
      t.constant = boolean(m["constant"]);
    out.push_back(std::move(t));
  }
  return out;
}

std::vector<PrescribedSpec> Validator::prescribed(const Item& it, const CaseSpec& spec) const {
  std::vector<PrescribedSpec> out;
  const Vec2 lo = spec.grid.origin, hi = spec.grid.origin + spec.grid.extent;
  const double tol = 1e-9 * spec.grid.cell_size;
  for (const Item& item : list(it)) {
    const Map m(*this, item, {"name", "min", "max", "displacement"});
    PrescribedSpec p;
    p.where = locate(m.self());
    const Item name_item = m.required("name");
    p.name = name(name_item);
    for (const auto& other : out)
      if (other.name == p.name)
        fail(name_item, "duplicate name '" + p.name + "'");
    p.min = vec2(m.required("min"));
    const Item max_item = m.required("max");
    p.max = vec2(max_item);
    if (!(p.max.x() >= p.min.x() && p.max.y() >= p.min.y()))
      fail(max_item, "max must not be below min in either direction");
    for (const auto& [key, corner] : {std::pair{"min", p.min}, std::pair{"max", p.max}})
      if ((corner.array() < lo.array() - tol).any() || (corner.array() > hi.array() + tol).any())
        fail(m[key], std::string(key) + " lies outside the grid");
    const Item d = m.required("displacement");
    if (!d.node.IsSequence() || d.node.size() != 2)
      fail(d, "expected a 2-element list [ux, uy]; write ~ (null) for a free component");
    for (std::size_t i = 0; i < 2; ++i) {
      const Item c{d.node[i], mark_or(d.node[i], d.mark), child_path(d.path, i)};
      if (c.node.IsNull())
        continue;
      p.displacement[i] = number(c);
    }
    if (!p.displacement[0] && !p.displacement[1])
      fail(d, "both components are free (~); prescribe at least one");
    if (const std::string stage = explicit_stage(spec); !stage.empty())
      fail(m.self(), "prescribed displacements need an implicit analysis "
                     "(implicit_quasistatic or implicit_dynamic), but " +
                         stage + " is explicit");
    out.push_back(std::move(p));
  }
  return out;
}

// A fixed explicit step above h / c_p amplifies the stiffest mode of the grid (the CFL limit of
// the lumped-mass central-difference scheme); such a step is refused, not run into a blow-up.
// Velocities are checked while stepping: the run stops once dt (c_p + |v|) / h exceeds 1.
void Validator::check_explicit_time_step(const Item& time_item, const TimeSpec& time,
                                         const CaseSpec& spec) const {
  double fastest = 0;
  std::string material;
  for (const auto& body : spec.bodies)
    for (const auto& m : spec.materials)
      if (m.name == body.material) {
        const double nu = m.poisson_ratio;
        const double p_wave = m.youngs_modulus * (1 - nu) / ((1 + nu) * (1 - 2 * nu));
        if (const double c = std::sqrt(p_wave / m.density); c > fastest) {
          fastest = c;
          material = m.name;
        }
      }
  const double limit = spec.grid.cell_size / fastest;
  if (*time.dt > limit) {
    const Map time_map(*this, time_item, {"end_time", "cfl", "dt", "max_steps", "min_dt"});
    fail(time_map["dt"],
         fmt::format("explicit time step {:g} s is above the stability limit h / c_p = {:g} s "
                     "(cell size {:g} m, p-wave speed {:g} m/s of material '{}'); use dt <= "
                     "{:g} or set time.cfl instead",
                     *time.dt, limit, spec.grid.cell_size, fastest, material, limit));
  }
}

// An implicit analysis steps by dt (its first load step); an explicit one by dt or a CFL number.
void Validator::check_time_step(const Item& time_item, AnalysisType analysis, const TimeSpec& time,
                                const CaseSpec& spec) const {
  if (analysis != AnalysisType::Explicit && time.cfl) {
    const Map time_map(*this, time_item, {"end_time", "cfl", "dt", "max_steps", "min_dt"});
    fail(time_map["cfl"], "a CFL number applies to explicit analyses; an implicit analysis "
                          "needs 'dt', its initial load step");
  }
  if (analysis == AnalysisType::Explicit && time.dt)
    check_explicit_time_step(time_item, time, spec);
}

std::vector<StageSpec> Validator::stages(const Item& it, const CaseSpec& spec) const {
  std::vector<StageSpec> out;
  UniqueNames names(*this, "stage");
  for (const Item& item : list(it)) {
    const Map m(*this, item,
                {"name", "analysis", "time", "strength_factor", "wall_time_limit", "at_rest"});
    StageSpec s;
    s.where = locate(m.self());
    s.name = name(m.required("name"));
    names.add(s.name, m["name"], item.path);
    s.analysis = analysis(m.required("analysis"));
    const Item time_item = m.required("time");
    s.time = time(time_item);
    check_time_step(time_item, s.analysis, s.time, spec);
    if (m.has("strength_factor")) {
      s.strength_factor = positive(m["strength_factor"]);
      if (!has_reducible_material(spec.materials))
        fail(m["strength_factor"], "a strength factor divides cohesion and tan(friction_angle); "
                                   "the case has no tresca, mohr_coulomb or drucker_prager "
                                   "material");
    }
    if (m.has("wall_time_limit"))
      s.wall_time_limit = positive(m["wall_time_limit"]);
    if (m.present("at_rest")) {
      if (s.analysis == AnalysisType::ImplicitQuasistatic)
        fail(m.key("at_rest"), "'at_rest' reads the kinetic energy; a quasi-static stage has "
                               "none (use implicit_dynamic or explicit)");
      const Map rest(*this, m["at_rest"], {"kinetic_energy_ratio", "duration"});
      RestCriterion r;
      if (rest.has("kinetic_energy_ratio")) {
        const Item ratio = rest["kinetic_energy_ratio"];
        r.kinetic_energy_ratio = number(ratio);
        if (!(r.kinetic_energy_ratio > 0 && r.kinetic_energy_ratio < 1))
          fail(ratio, "must be in the open interval (0, 1) (got " + ratio.node.Scalar() + ")");
      }
      if (rest.has("duration"))
        r.duration = positive(rest["duration"]);
      s.at_rest = r;
    }
    out.push_back(std::move(s));
  }
  if (out.empty())
    fail(it, "'stages' lists no stage");
  return out;
}

TimeSpec Validator::time(const Item& it) const {
  const Map m(*this, it, {"end_time", "cfl", "dt", "max_steps", "min_dt"});
  TimeSpec t;
  t.end_time = positive(m.required("end_time"));
  if (m.has("cfl")) {
    const Item cfl = m["cfl"];
    t.cfl = number(cfl);
    if (!(*t.cfl > 0 && *t.cfl < 1))
      fail(cfl, "must be in the open interval (0, 1) (got " + cfl.node.Scalar() + ")");
  }
  if (m.has("dt"))
    t.dt = positive(m["dt"]);
  if (t.cfl && t.dt)
    fail(m.key("dt"), "give exactly one of 'cfl' and 'dt', not both");
  if (!t.cfl && !t.dt)
    fail(m.self(), "missing required key 'cfl' or 'dt' (give exactly one)");
  if (m.has("min_dt")) {
    t.min_dt = positive(m["min_dt"]);
    if (t.dt && *t.min_dt > *t.dt)
      fail(m["min_dt"], "must not exceed dt");
  }
  if (m.has("max_steps")) {
    const Item max_steps = m["max_steps"];
    t.max_steps = integer(max_steps);
    if (t.max_steps < 1)
      fail(max_steps, "must be an integer >= 1 (got " + max_steps.node.Scalar() + ")");
  }
  return t;
}

/// The output defaults: the six fields, plus plastic_strain when the case has an
/// elasto-plastic material.
OutputSpec default_output(bool any_plastic) {
  OutputSpec o;
  if (any_plastic)
    o.fields.push_back(OutputField::PlasticStrain);
  return o;
}

OutputSpec Validator::output(const Item& it, bool any_plastic) const {
  const Map m(*this, it,
              {"every_steps", "every_time", "fields", "stress_recovery", "voxels", "pattern_size"});
  OutputSpec o = default_output(any_plastic);
  if (m.has("every_steps")) {
    const Item every = m["every_steps"];
    o.every_steps = integer(every);
    if (*o.every_steps < 1)
      fail(every, "must be an integer >= 1 (got " + every.node.Scalar() + ")");
  }
  if (m.has("every_time"))
    o.every_time = positive(m["every_time"]);
  if (o.every_steps && o.every_time)
    fail(m.key("every_time"), "give at most one of 'every_steps' and 'every_time'");
  if (m.has("fields")) {
    o.fields.clear();
    for (const Item& f : list(m["fields"])) {
      const OutputField field =
          choice<OutputField>(f, {{"velocity", OutputField::Velocity},
                                  {"mass", OutputField::Mass},
                                  {"volume", OutputField::Volume},
                                  {"F", OutputField::DeformationGradient},
                                  {"stress", OutputField::Stress},
                                  {"material", OutputField::Material},
                                  {"plastic_strain", OutputField::PlasticStrain},
                                  {"reference_position", OutputField::ReferencePosition}});
      if (std::find(o.fields.begin(), o.fields.end(), field) != o.fields.end())
        fail(f, "field '" + f.node.Scalar() + "' is listed twice");
      if (field == OutputField::PlasticStrain && !any_plastic)
        fail(f, "field 'plastic_strain' needs an elasto-plastic material (von_mises, tresca, "
                "mohr_coulomb, drucker_prager); every material of this case is elastic");
      o.fields.push_back(field);
    }
  }
  if (m.has("stress_recovery"))
    o.stress_recovery = boolean(m["stress_recovery"]);
  if (m.has("voxels"))
    o.voxels = boolean(m["voxels"]);
  if (m.has("pattern_size")) {
    o.pattern_size = positive(m["pattern_size"]);
    if (!o.voxels)
      fail(m.key("pattern_size"), "'pattern_size' colours the voxels; it needs 'voxels: true'");
  }
  return o;
}

std::vector<ProbeSpec> Validator::probes(const Item& it) const {
  std::vector<ProbeSpec> out;
  UniqueNames names(*this, "probe");
  for (const Item& item : list(it)) {
    const Map m(*this, item, {"name", "point", "particle"});
    ProbeSpec p;
    p.where = locate(m.self());
    const Item name_item = m.required("name");
    p.name = name(name_item);
    names.add(p.name, name_item, item.path);
    if (m.has("point") && m.has("particle"))
      fail(m.key("particle"), "give exactly one of 'point' and 'particle', not both");
    if (m.has("point")) {
      p.point = vec2(m["point"]);
    } else if (m.has("particle")) {
      const Item particle = m["particle"];
      p.particle = integer(particle);
      if (*p.particle < 0)
        fail(particle, "must be an integer >= 0 (got " + particle.node.Scalar() + ")");
    } else {
      fail(m.self(), "missing required key 'point' or 'particle' (give exactly one)");
    }
    out.push_back(std::move(p));
  }
  return out;
}

SolverSpec Validator::solver(const Item& it, const CaseSpec& spec) const {
  const Map m(*this, it, solver_keys());
  SolverSpec s;
  if (m.has("shape"))
    s.shape = choice<ShapeFunction>(
        m["shape"], {{"gimp", ShapeFunction::Gimp}, {"linear", ShapeFunction::Linear}});
  if (m.has("scheme"))
    s.scheme = choice<UpdateScheme>(
        m["scheme"],
        {{"usl", UpdateScheme::USL}, {"usf", UpdateScheme::USF}, {"musl", UpdateScheme::MUSL}});
  if (m.has("flip")) {
    const Item flip = m["flip"];
    s.flip = number(flip);
    if (!(s.flip >= 0 && s.flip <= 1))
      fail(flip, "must be in [0, 1] (got " + flip.node.Scalar() + ")");
  }
  if (m.has("linear_solver")) {
    const Item ls = m["linear_solver"];
    LinearSolverKind kind;
    if (!ls.node.IsScalar() || !parse_linear_solver_kind(ls.node.Scalar(), kind))
      fail(ls, "unknown linear solver '" + (ls.node.IsScalar() ? ls.node.Scalar() : "") +
                   "' (built in: " + join(available_linear_solvers()) + ")");
    s.linear_solver = ls.node.Scalar();
  }
  if (m.has("newton_tolerance")) {
    const Item tol = m["newton_tolerance"];
    s.newton_tolerance = positive(tol);
    if (s.newton_tolerance >= 1e-2)
      fail(tol, "must be below 1e-2 (got " + tol.node.Scalar() + ")");
  }
  if (m.has("max_newton_iterations")) {
    const Item it_max = m["max_newton_iterations"];
    const Index v = integer(it_max);
    if (v < 1 || v > 200)
      fail(it_max, "must be an integer in [1, 200] (got " + it_max.node.Scalar() + ")");
    s.max_newton_iterations = static_cast<int>(v);
  }
  if (m.has("easy_newton_iterations")) {
    const Item easy = m["easy_newton_iterations"];
    const Index v = integer(easy);
    if (v < 1 || v > s.max_newton_iterations)
      fail(easy, fmt::format("must be an integer in [1, max_newton_iterations = {}] (got {})",
                             s.max_newton_iterations, easy.node.Scalar()));
    s.easy_newton_iterations = static_cast<int>(v);
  }
  if (m.has("ghost_penalty")) {
    const Item gp = m["ghost_penalty"];
    if (!any_implicit_stage(spec))
      fail(m.key("ghost_penalty"), "'ghost_penalty' stabilises the implicit grid solve; an "
                                   "explicit analysis has no tangent to stabilise");
    s.ghost_penalty = number(gp);
    if (!(s.ghost_penalty >= 0 && s.ghost_penalty < 1))
      fail(gp, "must be in [0, 1) (got " + gp.node.Scalar() + ")");
  }
  if (m.has("f_bar")) {
    if (const std::string stage = explicit_stage(spec); !stage.empty())
      fail(m.key("f_bar"), "'f_bar' averages the volume change of the implicit grid solve; "
                           "explicit analyses do not support it, and " +
                               stage + " is explicit");
    s.f_bar = boolean(m["f_bar"]);
  }
  if (m.has("transfer")) {
    s.transfer = choice<TransferScheme>(
        m["transfer"], {{"flip", TransferScheme::Flip}, {"apic", TransferScheme::Apic}});
    if (s.transfer == TransferScheme::Apic && any_implicit_stage(spec))
      fail(m["transfer"], "transfer 'apic' is implemented in the explicit analysis only; the "
                          "implicit analyses transfer with FLIP/PIC (set 'flip')");
    if (s.transfer == TransferScheme::Apic && s.shape == ShapeFunction::Linear)
      fail(m["transfer"], "transfer 'apic' needs shape 'gimp': with linear hats APIC's affine "
                          "moment D_p vanishes whenever a point sits on a node, and the transfer "
                          "is unstable");
  }
  return s;
}

StrengthReductionSpec Validator::strength_reduction(const Item& it, const CaseSpec& spec) const {
  const Map m(*this, it,
              {"lower", "upper", "tolerance", "max_trials", "probe", "displacement_limit"});
  StrengthReductionSpec s;
  s.where = locate(m.self());
  // Each trial is a quasi-static loading whose failure is Newton's; the other analyses have
  // no such criterion.
  if (!spec.stages.empty())
    fail(m.self(), "strength reduction runs its own quasi-static trials from scratch; it cannot "
                   "be combined with 'stages'");
  if (spec.analysis != AnalysisType::ImplicitQuasistatic)
    fail(m.self(), "strength reduction loads the case quasi-statically; it needs 'analysis: "
                   "implicit_quasistatic'");
  if (!has_reducible_material(spec.materials))
    fail(m.self(), "strength reduction divides cohesion and tan(friction_angle); the case has "
                   "no tresca, mohr_coulomb or drucker_prager material");
  if (m.has("lower"))
    s.lower = positive(m["lower"]);
  if (m.has("upper"))
    s.upper = positive(m["upper"]);
  if (!(s.upper > s.lower))
    fail(m.has("upper") ? m["upper"] : m.self(),
         fmt::format("'upper' ({:g}) must be above 'lower' ({:g})", s.upper, s.lower));
  if (m.has("tolerance"))
    s.tolerance = positive(m["tolerance"]);
  if (m.has("max_trials")) {
    const Item trials = m["max_trials"];
    const Index v = integer(trials);
    if (v < 2 || v > 100)
      fail(trials, "must be an integer in [2, 100] (got " + trials.node.Scalar() + ")");
    s.max_trials = static_cast<int>(v);
  }
  const Item probe = m.required("probe");
  s.probe = name(probe);
  if (std::none_of(spec.probes.begin(), spec.probes.end(),
                   [&](const ProbeSpec& p) { return p.name == s.probe; }))
    fail(probe, "no probe named '" + s.probe + "' (the crest probe must be listed in 'probes')");
  if (m.has("displacement_limit"))
    s.displacement_limit = positive(m["displacement_limit"]);
  return s;
}

CaseSpec Validator::read(const YAML::Node& root) const {
  const Item top_item{root, root.Mark(), ""};
  if (root.IsNull() || !root.IsDefined())
    fail(top_item, "the case file is empty");
  if (!root.IsMap())
    fail(top_item, "a case file must be a map of keys (name:, grid:, ...), got " + describe(root));
  const Map top(*this, top_item,
                {"name", "analysis", "dimension", "grid", "materials", "bodies", "gravity",
                 "boundaries", "point_loads", "tractions", "prescribed", "time", "output", "probes",
                 "solver", "strength_reduction", "stages"});
  CaseSpec spec;
  spec.name = case_name(top.required("name"));
  if (top.has("analysis") && !top.present("stages"))
    spec.analysis = analysis(top["analysis"]);
  if (top.has("dimension"))
    spec.dimension = dimension(top["dimension"]);
  spec.grid = grid(top.required("grid"));
  spec.materials = materials(top.required("materials"));
  if (top.has("gravity"))
    spec.gravity = vec2(top["gravity"]);
  spec.bodies = bodies(top.required("bodies"), spec);
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
  if (top.present("boundaries"))
    spec.boundaries = boundaries(top["boundaries"]);
  if (top.present("point_loads"))
    spec.point_loads = point_loads(top["point_loads"]);
  if (top.present("tractions"))
    spec.tractions = tractions(top["tractions"], spec);
  if (top.present("prescribed"))
    spec.prescribed = prescribed(top["prescribed"], spec);
  const bool any_plastic = std::any_of(spec.materials.begin(), spec.materials.end(),
                                       [](const MaterialSpec& m) { return is_plastic(m.model); });
  spec.output =
      top.present("output") ? output(top["output"], any_plastic) : default_output(any_plastic);
  if (top.present("probes"))
    spec.probes = probes(top["probes"]);
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
        if (is_plastic(material.model) && nonsymmetric_tangent(material))
          refuse("material '" + material.name + "' has non-associated flow or softening");
    }
  }
  if (top.present("strength_reduction"))
    spec.strength_reduction = strength_reduction(top["strength_reduction"], spec);
  return spec;
}

} // namespace

CaseSpec read_case_text(const std::string& text, const std::string& label,
                        const std::vector<std::string>& overrides) {
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
    throw InputError(
        SourceLocation{label, m.is_null() ? 0 : m.line + 1, m.is_null() ? 0 : m.column + 1, ""},
        "YAML syntax error: " + e.msg);
  }

  // A document that is not a map is reported as such before any override tries to go into it.
  if (!root.IsNull() && !root.IsMap())
    Validator(label, {}).read(root);
  std::vector<AppliedOverride> applied = detail::apply_overrides(root, overrides);

  CaseSpec spec = Validator(label, std::move(applied)).read(root);
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
