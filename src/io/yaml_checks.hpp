#pragma once
// Internal to the case reader: checks of the raw YAML text that yaml-cpp would otherwise
// misreport (a file with CR-only line ends, nesting past yaml-cpp's depth limit, a quoted string
// that is never closed), so that each gets a message that says what is really wrong, and where.
#include <yaml-cpp/yaml.h>

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace talus::detail {

/// Deepest nesting of maps and lists a case file may have (checked on the tree, with the key
/// path). A case needs about 6 levels.
inline constexpr int kMaxNesting = 64;
/// Nesting the raw text may show before it is parsed: yaml-cpp gives up at about 500 levels with
/// "bad file" and no useful position, so deeper text is refused before yaml-cpp sees it.
inline constexpr int kMaxTextNesting = 400;

/// What is wrong in a text and where (0-based byte offset into it).
struct TextProblem {
  std::size_t offset = 0;
  std::string what;
};

/// A carriage return that is not followed by a line feed (old Mac line ends, which yaml-cpp reads
/// as no line end at all), or nesting deeper than kMaxTextNesting. Quoted strings and comments are
/// skipped; the nesting count is an upper bound of what the parser will see.
std::optional<TextProblem> check_raw_text(std::string_view text);

/// True when the scalar whose node starts at `mark` in `text` opens with a quote (' or ") that is
/// never closed: yaml-cpp then takes the rest of the file as the string's text.
bool quote_unterminated(std::string_view text, const YAML::Mark& mark);

/// The mark of the first quoted scalar under `node` (keys included) that quote_unterminated finds.
std::optional<YAML::Mark> find_unterminated_quote(const YAML::Node& node, std::string_view text);

/// The message for an unterminated quote that opens at `mark`.
std::string unterminated_quote_message(std::string_view text, const YAML::Mark& mark);

/// The key path of the block mapping entries that enclose a byte offset ("grid.origin",
/// "bodies[1].vertices"), read from the indentation of the lines up to it, for problems found
/// before the text is parsed; "" when the offset lies before the first key. Flow collections
/// ([...] and {...}) are not entered: the path ends at the key that holds them.
std::string enclosing_key_path(std::string_view text, std::size_t offset);

/// 1-based line and column of a byte offset.
std::pair<int, int> line_column(std::string_view text, std::size_t offset);

} // namespace talus::detail
