#pragma once
// Internal helpers of the case reader (not installed, not part of the public API):
// --set overrides applied to a yaml-cpp tree, and "did you mean" suggestions.
#include <yaml-cpp/yaml.h>

#include <string>
#include <string_view>
#include <vector>

namespace talus::detail {

/// One --set override after it was applied: the canonical key path it replaced (list items by
/// index, e.g. "materials[0].youngs_modulus" for "materials.disc.youngs_modulus") and its text.
struct AppliedOverride {
  std::string path;
  std::string text;
};

/// Applies `overrides` ("key.path=value") in order to `root` (a map, or null for an empty
/// document, which becomes a map). Path elements: map keys, list indices as "[i]" or ".i", or the
/// `name` of a list item. Missing map keys are created. Setting time.dt removes time.cfl (and
/// vice versa); setting output.every_steps removes output.every_time (and vice versa).
/// Throws InputError with file "--set" for a malformed override.
std::vector<AppliedOverride> apply_overrides(YAML::Node& root,
                                             const std::vector<std::string>& overrides);

/// `text` as a message quotes it: at most `cap` characters (then "..."), every byte that is not
/// printable UTF-8 written as \xNN, so a 5 MB value or a binary key costs a line, not a screen.
std::string shown(std::string_view text, std::size_t cap = 80);

/// Offset of the first byte of `text` that is not part of valid UTF-8 (overlong forms, surrogates
/// and code points above U+10FFFF count as invalid), or npos.
std::size_t invalid_utf8_at(std::string_view text);

/// Levenshtein distance.
std::size_t edit_distance(std::string_view a, std::string_view b);

/// The candidate closest to `word` if it is close enough to be a plausible typo, else "". Words
/// longer than kMaxSuggestedWord get no suggestion (no key is that long, and the distance costs
/// length x length).
inline constexpr std::size_t kMaxSuggestedWord = 64;
std::string closest_match(std::string_view word, const std::vector<std::string>& candidates);

/// "a, b, c"
std::string join(const std::vector<std::string>& items, std::string_view separator = ", ");

/// Appends a map key or a list index to a key path ("a" + "b" -> "a.b", "a" + 0 -> "a[0]").
std::string child_path(const std::string& parent, const std::string& key);
std::string child_path(const std::string& parent, std::size_t index);

} // namespace talus::detail
