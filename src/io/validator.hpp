#pragma once
// Internal to the case reader (src/io/): the Validator that turns the YAML tree into a CaseSpec,
// the Item (a value, where it came from and its key path) and the checked Map of keys. The
// sections of the case are read in their own files (read_*.cpp), all through one Validator.
#include "talus/core/errors.hpp"
#include "talus/core/expression.hpp"
#include "talus/io/case_vocabulary.hpp"
#include "talus/spec/case_spec.hpp"

#include "validator_support.hpp"
#include "yaml_support.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <fmt/format.h>
#include <map>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>
#include <yaml-cpp/yaml.h>

namespace talus::detail {

/// A value in the case tree and where it came from.
struct Item {
  YAML::Node node;
  YAML::Mark mark; ///< of the value; of its key when the value is empty
  std::string path;
};

inline YAML::Mark mark_or(const YAML::Node& n, const YAML::Mark& fallback) {
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
  /// `text` is the case file's text (the marks of the tree point into it); it must outlive the
  /// Validator.
  Validator(std::string file, std::vector<AppliedOverride> overrides, std::string_view text = {})
      : file_(std::move(file)), overrides_(std::move(overrides)), text_(text) {}

  /// The checks of the whole tree before any section is read: no YAML tags, no quoted string
  /// left open, a bounded number of values (aliases can multiply them). Throws InputError.
  void check_tree(const YAML::Node& root) const;

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
  /// Records where a map's value sat, for CaseSpec::locations.
  void note_location(const Item& value) const { locations_[value.path] = locate(value); }

  [[noreturn]] void fail(const Item& at, const std::string& what) const {
    std::string message = what;
    if (const AppliedOverride* o = origin(at.mark, at.path))
      message += " (from --set " + shown(o->text, 200) + ")";
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
  /// A name: non-empty, at most 255 bytes of printable UTF-8. Names end up in directory names,
  /// run.h5, summary.json and the column names of timeseries.csv, which hold UTF-8 text.
  std::string name(const Item& it) const {
    std::string s = text(it);
    if (s.empty())
      fail(it, "a name must not be empty");
    if (const std::size_t bad = invalid_utf8_at(s); bad != std::string::npos)
      fail(it, fmt::format("the name '{}' is not valid UTF-8 (byte 0x{:02x} at position {}); names "
                           "go into result files that hold UTF-8 text",
                           shown(s), static_cast<unsigned char>(s[bad]), bad));
    for (const char c : s)
      if (static_cast<unsigned char>(c) < 0x20 || c == 0x7F)
        fail(it, "the name '" + shown(s) +
                     "' holds a control character (a tab, a line break, ...); names go into "
                     "result files and column names");
    if (s.size() > 255)
      fail(it, fmt::format("the name '{}' is {} bytes long; at most 255 (it may become a "
                           "directory name)",
                           shown(s), s.size()));
    return s;
  }

  double number(const Item& it) const { return parse_number(it, "a number"); }

  /// A name that becomes part of a column name of timeseries.csv (probes, prescribed boxes).
  void column_name(const Item& it, const std::string& s) const {
    if (s.find_first_of(",\"") != std::string::npos)
      fail(it, "the name '" + shown(s) +
                   "' holds a comma or a double quote; it names columns of timeseries.csv");
  }

  /// A finite number; `expected` names the kind for "expected X, got Y".
  /// s in lower case without a leading sign: how YAML and strtod spell infinities and NaNs.
  static std::string unsigned_lower_case(const std::string& s) {
    std::string lower;
    for (char c : s)
      lower += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (!lower.empty() && (lower[0] == '+' || lower[0] == '-'))
      lower.erase(0, 1);
    return lower;
  }
  static bool names_infinity_or_nan(const std::string& s) {
    const std::string lower = unsigned_lower_case(s);
    return lower == ".inf" || lower == "inf" || lower == "infinity" || lower == ".nan" ||
           lower == "nan";
  }
  double parse_number(const Item& it, const std::string& expected) const {
    const YAML::Node& n = it.node;
    if (!n.IsScalar() || n.Tag() == "!" || n.Tag() == "tag:yaml.org,2002:str")
      fail(it, "expected " + expected + ", got " + describe(n));
    const std::string& s = n.Scalar();
    if (names_infinity_or_nan(s))
      fail(it, "must be a finite number (got " + shown(s) + "); NaN and infinity are not physical");
    const char* begin = s.data();
    const char* end = s.data() + s.size();
    if (begin != end && *begin == '+')
      ++begin;
    double v = 0;
    const auto [ptr, ec] = std::from_chars(begin, end, v);
    if (ec == std::errc::result_out_of_range)
      fail(it, "number " + shown(s) + " is out of the double-precision range");
    if (ec != std::errc() || ptr != end || begin == end)
      fail(it, "expected " + expected + ", got " + describe(n));
    if (!std::isfinite(v))
      fail(it, "must be a finite number (got " + shown(s) + ")");
    return v;
  }

  Index integer(const Item& it) const {
    const YAML::Node& n = it.node;
    const double v = parse_number(it, "an integer");
    if (v != std::floor(v))
      fail(it, "expected an integer, got " + describe(n));
    if (std::abs(v) > 9.0e15)
      fail(it, "integer " + shown(n.Scalar()) + " is out of range");
    return static_cast<Index>(v);
  }

  /// A count: an integer >= 1 (every N steps, at most N steps).
  Index count(const Item& it) const {
    const Index n = integer(it);
    if (n < 1)
      fail(it, "must be an integer >= 1 (got " + shown(it.node.Scalar()) + ")");
    return n;
  }

  /// "a 2-element list [x, y]" or "a 3-element list [x, y, z]": what a point of the case is.
  std::string point_list() const {
    return dimension_ == 3 ? "a 3-element list [x, y, z]" : "a 2-element list [x, y]";
  }

  /// A point or vector of the case: as many numbers as it has dimensions (z = 0 in 2D).
  Vec3 point(const Item& it) const {
    const YAML::Node& n = it.node;
    if (!n.IsSequence())
      fail(it, "expected " + point_list() + ", got " + describe(n));
    if (n.size() != static_cast<std::size_t>(dimension_))
      fail(it, fmt::format("expected {} (dimension: {}), got a list of {} element{}", point_list(),
                           dimension_, n.size(), n.size() == 1 ? "" : "s"));
    Vec3 v = Vec3::Zero();
    for (std::size_t i = 0; i < n.size(); ++i)
      v[static_cast<Eigen::Index>(i)] =
          number(Item{n[i], mark_or(n[i], it.mark), child_path(it.path, i)});
    return v;
  }

  /// A point of a plane figure (polygon vertices, a prism's section): [x, y].
  Vec2 plane_point(const Item& it) const {
    const YAML::Node& n = it.node;
    if (!n.IsSequence() || n.size() != 2)
      fail(it, "expected a 2-element list [x, y], got " + describe(n));
    Vec2 v;
    for (std::size_t i = 0; i < 2; ++i)
      v[static_cast<Eigen::Index>(i)] =
          number(Item{n[i], mark_or(n[i], it.mark), child_path(it.path, i)});
    return v;
  }

  /// True for text that is meant as a number, valid or not (1e5, -3, 1e400, .inf, .nan), as
  /// opposed to an expression such as 0.1*sin(x).
  static bool looks_numeric(const std::string& s) {
    if (names_infinity_or_nan(s))
      return true;
    const std::string lower = unsigned_lower_case(s);
    char* end = nullptr;
    std::strtod(lower.c_str(), &end);
    return !lower.empty() && end == lower.c_str() + lower.size();
  }

  /// A list of as many elements as the case has dimensions, each a number or an expression of
  /// the initial position (quoted text such as "0.01 * sin(pi / 50 * x)"); expressions are
  /// parsed here so a typo is reported with its location.
  void position_field(const Item& it, Vec3& values, std::array<std::string, 3>& expressions) const {
    const YAML::Node& n = it.node;
    if (!n.IsSequence() || n.size() != static_cast<std::size_t>(dimension_))
      fail(it, "expected " + point_list() + " of numbers or expressions of the position, got " +
                   (n.IsSequence()
                        ? fmt::format("a list of {} element{}", n.size(), n.size() == 1 ? "" : "s")
                        : describe(n)));
    values.setZero();
    for (std::size_t i = 0; i < n.size(); ++i) {
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
        const PositionExpression check(element.node.Scalar(), dimension_);
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
    std::string what = "unknown value '" + shown(s) + "' (allowed: " + join(names) + ")";
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
      fail(it, "must be > 0 (got " + shown(it.node.Scalar()) + ")");
    return v;
  }

private:
  std::string case_name(const Item& it) const;
  AnalysisType analysis(const Item& it) const;
  int dimension(const Item& it) const;
  Geometry geometry(const Item& it) const;
  GridSpec grid(const Item& it) const;
  std::vector<MaterialSpec> materials(const Item& it, const Vec3& gravity) const;
  std::vector<PlausibilityCheck> silenced_warnings(const Item& it) const;
  double density(const Map& m, const Vec3& gravity) const;
  std::optional<double> saturated_density(const Map& m, const Vec3& gravity) const;
  /// `stage`: a stage's water, which moves the table only.
  WaterSpec water(const Item& it, const CaseSpec& spec, bool stage = false) const;
  std::array<bool, 6> drained_faces(const Item& it) const;
  std::optional<PoreFlowSpec> pore_flow(const Map& m) const;
  void check_consolidation(const Map& top, const CaseSpec& spec) const;
  std::vector<BodySpec> bodies(const Item& it, const CaseSpec& spec) const;
  void body_shape(const Map& m, BodySpec& b) const;
  void body_inside_grid(const Map& m, const BodySpec& b, const GridSpec& g) const;
  /// Axisymmetry: the body lies in r = x >= 0 (a body of revolution cannot cross its axis).
  void body_off_axis(const Map& m, const BodySpec& b) const;
  BoundarySpec boundaries(const Item& it, const CaseSpec& spec) const;
  std::vector<PointLoadSpec> point_loads(const Item& it, const CaseSpec& spec) const;
  std::vector<TractionSpec> tractions(const Item& it, const CaseSpec& spec) const;
  std::vector<PrescribedSpec> prescribed(const Item& it, const CaseSpec& spec) const;
  TimeSpec time(const Item& it) const;
  std::vector<StageSpec> stages(const Item& it, const CaseSpec& spec) const;
  void check_time_step(const Item& time_item, AnalysisType analysis, const TimeSpec& time,
                       const CaseSpec& spec) const;
  void check_explicit_time_step(const Item& time_item, const TimeSpec& time,
                                const CaseSpec& spec) const;
  OutputSpec output(const Item& it, bool any_plastic, bool water) const;
  std::vector<ProbeSpec> probes(const Item& it, const GridSpec& grid) const;
  void bodies_apart(const std::vector<Item>& items, const std::vector<BodySpec>& bodies,
                    const GridSpec& grid) const;
  SolverSpec solver(const Item& it, const CaseSpec& spec) const;
  /// The strength_reduction section; its flow_rule goes to spec.strength_flow_rule.
  StrengthReductionSpec strength_reduction(const Item& it, CaseSpec& spec) const;
  /// A staged case's strength_reduction: the stages its `after` names (all by default).
  std::vector<std::size_t> stages_searched(const Map& m, StrengthReductionMode mode,
                                           const CaseSpec& spec) const;
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
        v_.fail(where, "duplicate " + kind_ + " name '" + shown(name) + "' (already used by " +
                           it->second + ")");
    }

  private:
    const Validator& v_;
    std::string kind_;
    std::map<std::string, std::string> seen_;
  };

  void check_node(const Item& it, int depth, std::size_t& count) const;
  void check_memory(const Map& top, const CaseSpec& spec) const;

  std::string file_;
  std::vector<AppliedOverride> overrides_;
  std::string_view text_;
  /// The case's dimension, known once the top level's `dimension` is read: the points read
  /// after it have as many components.
  mutable int dimension_ = 2;
  mutable bool axisymmetric_ = false; ///< the case's geometry, known with its dimension
  mutable std::map<std::string, SourceLocation> locations_; ///< see note_location
};

/// The output defaults: the six fields, plus plastic_strain when the case has an
/// elasto-plastic material and pore_pressure when it has water.
OutputSpec default_output(bool any_plastic, bool water);

} // namespace talus::detail
