// --set overrides on the parsed case tree, plus the small string helpers the reader shares.
#include "yaml_checks.hpp"
#include "yaml_support.hpp"

#include "talus/core/errors.hpp"

#include <algorithm>
#include <cctype>
#include <optional>

namespace talus::detail {

std::size_t edit_distance(std::string_view a, std::string_view b) {
  // Optimal string alignment: insertions, deletions, substitutions and swaps of two neighbours
  // ("msul" -> "musl") each count 1.
  const std::size_t n = a.size(), m = b.size();
  std::vector<std::vector<std::size_t>> d(n + 1, std::vector<std::size_t>(m + 1));
  for (std::size_t i = 0; i <= n; ++i)
    d[i][0] = i;
  for (std::size_t j = 0; j <= m; ++j)
    d[0][j] = j;
  for (std::size_t i = 1; i <= n; ++i)
    for (std::size_t j = 1; j <= m; ++j) {
      const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  return d[n][m];
}

std::string closest_match(std::string_view word, const std::vector<std::string>& candidates) {
  if (word.size() > kMaxSuggestedWord)
    return "";
  // Allow one edit for very short words, otherwise about one edit in three characters (at
  // least two), which catches typos and transpositions without suggesting unrelated keys.
  const std::size_t limit = word.size() <= 3 ? 1 : std::max<std::size_t>(2, word.size() / 3);
  std::string best;
  std::size_t best_distance = limit + 1;
  for (const auto& candidate : candidates) {
    // The distance is at least the difference in length: no need to compute it then.
    const std::size_t gap = word.size() > candidate.size() ? word.size() - candidate.size()
                                                           : candidate.size() - word.size();
    if (gap > limit)
      continue;
    const std::size_t d = edit_distance(word, candidate);
    if (d < best_distance) {
      best_distance = d;
      best = candidate;
    }
  }
  return best;
}

std::size_t invalid_utf8_at(std::string_view text) {
  const auto* s = reinterpret_cast<const unsigned char*>(text.data());
  const std::size_t n = text.size();
  std::size_t i = 0;
  while (i < n) {
    const unsigned c = s[i];
    std::size_t len = 0;
    unsigned code = 0;
    if (c < 0x80) {
      ++i;
      continue;
    } else if ((c & 0xE0) == 0xC0) {
      len = 2;
      code = c & 0x1F;
    } else if ((c & 0xF0) == 0xE0) {
      len = 3;
      code = c & 0x0F;
    } else if ((c & 0xF8) == 0xF0) {
      len = 4;
      code = c & 0x07;
    } else {
      return i;
    }
    if (i + len > n)
      return i;
    for (std::size_t k = 1; k < len; ++k) {
      if ((s[i + k] & 0xC0) != 0x80)
        return i;
      code = (code << 6) | (s[i + k] & 0x3F);
    }
    const unsigned smallest[] = {0, 0, 0x80, 0x800, 0x10000};
    if (code < smallest[len] || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF))
      return i;
    i += len;
  }
  return std::string_view::npos;
}

std::string shown(std::string_view text, std::size_t cap) {
  std::string out;
  std::size_t chars = 0;
  std::size_t i = 0;
  while (i < text.size()) {
    if (chars == cap) {
      out += "...";
      break;
    }
    const auto c = static_cast<unsigned char>(text[i]);
    std::size_t len = 1;
    if (c >= 0x80) {
      len = (c & 0xE0) == 0xC0 ? 2 : (c & 0xF0) == 0xE0 ? 3 : (c & 0xF8) == 0xF0 ? 4 : 0;
      if (len == 0 || i + len > text.size() ||
          invalid_utf8_at(text.substr(i, len)) != std::string_view::npos)
        len = 0;
    }
    if (len == 0 || c < 0x20 || c == 0x7F) {
      static const char* digits = "0123456789abcdef";
      out += "\\x";
      out += digits[c >> 4];
      out += digits[c & 0xF];
      ++i;
    } else {
      out.append(text.substr(i, len));
      i += len;
    }
    ++chars;
  }
  return out;
}

std::string join(const std::vector<std::string>& items, std::string_view separator) {
  std::string out;
  for (std::size_t i = 0; i < items.size(); ++i) {
    if (i > 0)
      out += separator;
    out += items[i];
  }
  return out;
}

std::string child_path(const std::string& parent, const std::string& key) {
  return parent.empty() ? key : parent + "." + key;
}

std::string child_path(const std::string& parent, std::size_t index) {
  return parent + "[" + std::to_string(index) + "]";
}

namespace {

struct PathToken {
  std::string key;                  ///< a map key or a list item's name (when !index)
  std::optional<std::size_t> index; ///< set for "[i]" and for all-digit segments
  bool bracket = false;             ///< written as "[i]" (must be a list index)
};

class OverrideApplier {
public:
  explicit OverrideApplier(std::string text) : text_(std::move(text)) {}

  AppliedOverride apply(YAML::Node& root) {
    const auto eq = text_.find('=');
    if (eq == std::string::npos)
      fail("", "an override must have the form key.path=value (no '=' found)");
    const std::string path_text = trim(text_.substr(0, eq));
    const std::string value_text = text_.substr(eq + 1);
    const std::vector<PathToken> tokens = tokenize(path_text);

    if (root.IsNull())
      root = YAML::Node(YAML::NodeType::Map);
    if (!root.IsMap())
      fail("", "the case file is not a map of keys, so no key can be overridden");

    YAML::Node cur = root; // refers to the tree node; never assign to it, only reset()
    std::string path;
    for (std::size_t k = 0; k < tokens.size(); ++k) {
      const PathToken& t = tokens[k];
      const bool last = k + 1 == tokens.size();
      if (cur.IsSequence()) {
        const std::size_t i = list_position(cur, t, path);
        path = child_path(path, i);
        if (last) {
          YAML::Node item = cur[i];
          item = parse_value(value_text, path);
        } else {
          YAML::Node item = cur[i];
          descend(cur, item, path);
        }
      } else if (cur.IsMap()) {
        if (t.bracket)
          fail(path, "'" + path + "' is a map, not a list; use '." + std::to_string(*t.index) +
                         "' only for a key named '" + std::to_string(*t.index) + "'");
        const std::string key = t.index ? std::to_string(*t.index) : t.key;
        const std::string parent = path;
        path = child_path(path, key);
        if (last) {
          cur[key] = parse_value(value_text, path);
          remove_exclusive_partner(cur, parent, key);
        } else {
          YAML::Node child = cur[key];
          if (!child.IsDefined() || child.IsNull())
            child = YAML::Node(YAML::NodeType::Map); // create the missing map
          descend(cur, child, path);
        }
      } else {
        fail(path, "cannot go into '" + path + "': it holds the single value '" +
                       shown(cur.Scalar()) + "', not a map or a list");
      }
    }
    return AppliedOverride{path, text_};
  }

private:
  [[noreturn]] void fail(const std::string& key_path, const std::string& what) const {
    throw InputError(SourceLocation{"--set", 0, 0, shown(key_path, 200)},
                     what + " (in --set " + shown(text_, 200) + ")");
  }

  static std::string trim(const std::string& s) {
    std::size_t b = 0, e = s.size();
    while (b < e && std::isspace(static_cast<unsigned char>(s[b])))
      ++b;
    while (e > b && std::isspace(static_cast<unsigned char>(s[e - 1])))
      --e;
    return s.substr(b, e - b);
  }

  static bool all_digits(const std::string& s) {
    return !s.empty() &&
           std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isdigit(c) != 0; });
  }

  std::size_t parse_index(const std::string& digits) const {
    if (!all_digits(digits) || digits.size() > 9)
      fail("", "list index '" + shown(digits) + "' is not a non-negative integer");
    return static_cast<std::size_t>(std::stoul(digits));
  }

  std::vector<PathToken> tokenize(const std::string& s) const {
    if (s.empty())
      fail("", "empty key path before '='");
    std::vector<PathToken> tokens;
    std::size_t i = 0;
    while (true) {
      const std::size_t start = i;
      while (i < s.size() && s[i] != '.' && s[i] != '[' && s[i] != ']')
        ++i;
      PathToken key;
      key.key = s.substr(start, i - start);
      if (key.key.empty())
        fail("", "malformed key path '" + shown(s) + "' (empty element; write 'a[0]' or 'a.0')");
      if (all_digits(key.key))
        key.index = parse_index(key.key);
      tokens.push_back(std::move(key));
      while (i < s.size() && s[i] == '[') {
        const std::size_t close = s.find(']', i);
        if (close == std::string::npos)
          fail("", "malformed key path '" + shown(s) + "' (missing ']')");
        PathToken t;
        t.index = parse_index(s.substr(i + 1, close - i - 1));
        t.key = std::to_string(*t.index);
        t.bracket = true;
        tokens.push_back(std::move(t));
        i = close + 1;
      }
      if (i == s.size())
        break;
      if (s[i] != '.')
        fail("",
             "malformed key path '" + shown(s) + "' (unexpected '" + std::string(1, s[i]) + "')");
      ++i;
      if (i == s.size())
        fail("", "malformed key path '" + shown(s) + "' (ends with '.')");
    }
    return tokens;
  }

  /// Position in list `seq` (at `path`) addressed by `t`: an index, or an item's `name`.
  std::size_t list_position(const YAML::Node& seq, const PathToken& t,
                            const std::string& path) const {
    if (t.index) {
      if (*t.index >= seq.size())
        fail(path, "list index " + std::to_string(*t.index) + " is out of range: '" + path +
                       "' has " + std::to_string(seq.size()) + " item(s)");
      return *t.index;
    }
    std::vector<std::string> names;
    for (std::size_t i = 0; i < seq.size(); ++i) {
      const YAML::Node item = seq[i];
      if (!item.IsMap())
        continue;
      const YAML::Node name = item["name"];
      if (name.IsDefined() && name.IsScalar()) {
        if (name.Scalar() == t.key)
          return i;
        names.push_back(name.Scalar());
      }
    }
    std::string what = "no item named '" + shown(t.key) + "' in list '" + path + "'";
    if (names.empty())
      what += " (its items have no 'name'; use an index such as " + path + "[0])";
    else {
      what += " (names: " + join(names) + ")";
      const std::string guess = closest_match(t.key, names);
      if (!guess.empty())
        what += "; did you mean '" + guess + "'?";
    }
    fail(path, what);
  }

  void descend(YAML::Node& cur, const YAML::Node& child, const std::string& path) const {
    if (!child.IsMap() && !child.IsSequence())
      fail(path, "cannot go into '" + path + "': it holds the single value '" +
                     (child.IsScalar() ? shown(child.Scalar()) : std::string("")) +
                     "', not a map or a list");
    cur.reset(child);
  }

  YAML::Node parse_value(const std::string& value_text, const std::string& path) const {
    if (const std::optional<TextProblem> problem = check_raw_text(value_text))
      fail(path, "the value '" + shown(value_text) + "': " + problem->what);
    std::vector<YAML::Node> documents;
    try {
      documents = YAML::LoadAll(value_text);
    } catch (const YAML::ParserException& e) {
      fail(path, "the value '" + shown(value_text) + "' is not valid YAML: " + e.msg);
    }
    // A second document ("1e-3\n---\nfoo: 1") would be dropped without a word.
    if (documents.size() > 1)
      fail(path, "the value holds more than one YAML document (a '---' line starts another); "
                 "give one value per --set");
    if (documents.empty())
      return YAML::Node();
    if (const std::optional<YAML::Mark> open = find_unterminated_quote(documents[0], value_text))
      fail(path, "the value '" + shown(value_text) +
                     "': " + unterminated_quote_message(value_text, *open));
    return documents[0];
  }

  /// time.dt / time.cfl and output.every_steps / output.every_time exclude each other: setting
  /// one removes the other, so "--set time.dt=1e-4" works on a case that gives cfl.
  static void remove_exclusive_partner(YAML::Node& map, const std::string& parent,
                                       const std::string& key) {
    static const struct {
      const char* parent;
      const char* a;
      const char* b;
    } pairs[] = {{"time", "dt", "cfl"}, {"output", "every_steps", "every_time"}};
    for (const auto& p : pairs) {
      if (parent != p.parent)
        continue;
      if (key == p.a)
        map.remove(p.b);
      else if (key == p.b)
        map.remove(p.a);
    }
  }

  std::string text_;
};

} // namespace

std::vector<AppliedOverride> apply_overrides(YAML::Node& root,
                                             const std::vector<std::string>& overrides) {
  std::vector<AppliedOverride> applied;
  applied.reserve(overrides.size());
  for (const auto& text : overrides)
    applied.push_back(OverrideApplier(text).apply(root));
  return applied;
}

} // namespace talus::detail
