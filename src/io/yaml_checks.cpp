#include "yaml_checks.hpp"

#include <fmt/format.h>

#include <vector>

namespace talus::detail {

std::pair<int, int> line_column(std::string_view text, std::size_t offset) {
  int line = 1, column = 1;
  for (std::size_t i = 0; i < offset && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return {line, column};
}

std::string enclosing_key_path(std::string_view text, std::size_t offset) {
  // The open block levels: a map key, or a list item (its index), each with the column it
  // starts at. A line's content closes every level at or right of its column, but an item
  // marker "- " keeps a key of its own column (a list written flush with its key) and numbers
  // itself among the items of the key that holds the list.
  struct Level {
    std::size_t column;
    std::string key; // empty for a list item
    int index = 0;   // list item: its index; key: how many items its list has had
  };
  std::vector<Level> levels;
  int root_items = 0;
  for (std::size_t begin = 0; begin <= offset && begin < text.size();) {
    std::size_t end = text.find('\n', begin);
    if (end == std::string_view::npos)
      end = text.size();
    std::size_t i = begin;
    while (i < end && text[i] == ' ')
      ++i;
    const bool content = i < end && text[i] != '#' && text[i] != '\r' && i <= offset;
    if (content && i == begin && (text.substr(i, 3) == "---" || text.substr(i, 3) == "..."))
      levels.clear(); // a new document
    else if (content && !(i + 1 < end && text[i] == '-' && text[i + 1] == ' '))
      while (!levels.empty() && levels.back().column >= i - begin)
        levels.pop_back(); // anything that starts at or left of an open level closes it
    while (content && i + 1 < end && text[i] == '-' && text[i + 1] == ' ') {
      const std::size_t column = i - begin;
      while (!levels.empty() && (levels.back().column > column ||
                                 (levels.back().column == column && levels.back().key.empty())))
        levels.pop_back();
      int& count = levels.empty() ? root_items : levels.back().index;
      levels.push_back({column, "", count++});
      i += 2;
      while (i < end && text[i] == ' ')
        ++i;
    }
    if (content) {
      // "key:" followed by a space or the line's end opens a map entry at this column.
      std::size_t colon = i;
      while (colon < end && std::string_view(":[{\"'#").find(text[colon]) == std::string_view::npos)
        ++colon;
      if (colon < end && text[colon] == ':' && colon > i &&
          (colon + 1 == end || text[colon + 1] == ' ' || text[colon + 1] == '\r')) {
        const std::size_t column = i - begin;
        while (!levels.empty() && levels.back().column >= column)
          levels.pop_back();
        std::string_view key = text.substr(i, colon - i);
        while (!key.empty() && key.back() == ' ')
          key.remove_suffix(1);
        levels.push_back({column, std::string(key.substr(0, 64))});
      }
    }
    begin = end + 1;
  }
  std::string path;
  for (const Level& l : levels)
    path += l.key.empty() ? fmt::format("[{}]", l.index) : (path.empty() ? "" : ".") + l.key;
  return path;
}

std::optional<TextProblem> check_raw_text(std::string_view text) {
  for (std::size_t i = 0; i < text.size(); ++i)
    if (text[i] == '\r' && (i + 1 == text.size() || text[i + 1] != '\n'))
      return TextProblem{i, "the line ends here with a carriage return alone (old Mac line ends, "
                            "CR without LF), which YAML does not read as a line end; save the "
                            "file with LF or CRLF line ends"};

  // Block nesting: a stack of indentations (each "- " of a list item opens a level of its own);
  // flow nesting: open brackets. Quoted strings and comments do not count.
  std::vector<std::size_t> indents;
  std::size_t flow = 0;
  char quote = 0;
  bool line_start = true;
  std::size_t line_begin = 0;
  char previous = '\n'; // the last character on this line that is not a space
  bool comment = false;
  // The kind of the current document's root: yaml-cpp 0.7 loops forever (allocating) on a ','
  // where the root of a document should start, or after a root that is a flow collection.
  enum class Root { None, Block, Flow } root = Root::None;
  const auto stray_comma = [](std::size_t at) {
    return TextProblem{at, "a comma outside any [list] or {map}: it separates nothing here"};
  };
  const auto too_deep = [](std::size_t at) {
    return TextProblem{at, fmt::format("the maps and lists nest more than {} levels deep here (a "
                                       "case file needs fewer than 10); is a bracket or an "
                                       "indentation wrong?",
                                       kMaxTextNesting)};
  };
  const auto push_level = [&](std::size_t column) {
    while (!indents.empty() && indents.back() > column)
      indents.pop_back();
    if (indents.empty() || indents.back() < column)
      indents.push_back(column);
  };
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (quote != 0) {
      if (quote == '"' && c == '\\') {
        ++i;
      } else if (c == quote) {
        if (quote == '\'' && i + 1 < text.size() && text[i + 1] == '\'')
          ++i;
        else
          quote = 0;
      }
      continue;
    }
    if (c == '\n') {
      line_start = true;
      line_begin = i + 1;
      previous = '\n';
      comment = false;
      continue;
    }
    if (comment)
      continue;
    if (line_start) {
      if (c == ' ')
        continue;
      line_start = false;
      const bool at_column_0 = i == line_begin;
      if (at_column_0 && flow == 0 &&
          (text.compare(i, 3, "---") == 0 || text.compare(i, 3, "...") == 0) &&
          (i + 3 == text.size() || text[i + 3] == ' ' || text[i + 3] == '\n' ||
           text[i + 3] == '\r')) {
        root = Root::None; // a new document
        indents.clear();
        i += 2;
        continue;
      }
      // A line that starts with a comma outside brackets continues nothing a case file has,
      // and yaml-cpp 0.7 loops on it when it sits left of the root's indentation.
      if (c == ',' && flow == 0)
        return stray_comma(i);
      if (at_column_0 && c == '%' && root == Root::None) {
        comment = true; // a directive line
        continue;
      }
      if (flow == 0 && c != '#') {
        push_level(i - line_begin);
        // "- - x": every dash of a block list item opens one more level.
        std::size_t j = i;
        while (j < text.size() && text[j] == '-' &&
               (j + 1 == text.size() || text[j + 1] == ' ' || text[j + 1] == '\n')) {
          ++j;
          while (j < text.size() && text[j] == ' ')
            ++j;
          push_level(j - line_begin);
        }
        if (indents.size() > kMaxTextNesting)
          return too_deep(i);
      }
    }
    const char before = i == 0 ? '\n' : text[i - 1];
    if (c == '#' && (before == ' ' || before == '\n')) {
      comment = true;
      continue;
    }
    if (c != ' ' && c != '\t' && c != '\r' && root == Root::None) {
      if (c == ',')
        return stray_comma(i);
      root = (c == '[' || c == '{') ? Root::Flow : Root::Block;
    } else if (c == ',' && flow == 0 && root == Root::Flow) {
      return stray_comma(i);
    }
    const bool token_start =
        before == ' ' || before == '\n' || before == '[' || before == '{' || before == ',';
    if ((c == '"' || c == '\'') && token_start &&
        (previous == '\n' || previous == ':' || previous == '-' || previous == '[' ||
         previous == '{' || previous == ',' || previous == '?')) {
      quote = c;
      previous = c;
      continue;
    }
    if (c == '[' || c == '{') {
      ++flow;
      if (indents.size() + flow > kMaxTextNesting)
        return too_deep(i);
    } else if ((c == ']' || c == '}') && flow > 0) {
      --flow;
    }
    if (c != ' ')
      previous = c;
  }
  return std::nullopt;
}

bool quote_unterminated(std::string_view text, const YAML::Mark& mark) {
  if (mark.is_null() || mark.pos < 0 || static_cast<std::size_t>(mark.pos) >= text.size())
    return false;
  const auto start = static_cast<std::size_t>(mark.pos);
  const char quote = text[start];
  if (quote != '"' && quote != '\'')
    return false;
  for (std::size_t i = start + 1; i < text.size(); ++i) {
    if (quote == '"' && text[i] == '\\') {
      ++i;
    } else if (text[i] == quote) {
      if (quote == '\'' && i + 1 < text.size() && text[i + 1] == '\'')
        ++i;
      else
        return false;
    }
  }
  return true;
}

std::optional<YAML::Mark> find_unterminated_quote(const YAML::Node& node, std::string_view text) {
  if (node.IsScalar() && node.Tag() == "!" && quote_unterminated(text, node.Mark()))
    return node.Mark();
  if (node.IsSequence())
    for (const YAML::Node& item : node)
      if (auto mark = find_unterminated_quote(item, text))
        return mark;
  if (node.IsMap())
    for (auto it = node.begin(); it != node.end(); ++it) {
      if (auto mark = find_unterminated_quote(it->first, text))
        return mark;
      if (auto mark = find_unterminated_quote(it->second, text))
        return mark;
    }
  return std::nullopt;
}

std::string unterminated_quote_message(std::string_view text, const YAML::Mark& mark) {
  const char quote = text[static_cast<std::size_t>(mark.pos)];
  return fmt::format("unterminated quoted string: the {} opened here is never closed, so the rest "
                     "of the file was read as its text; add the closing {}",
                     quote, quote);
}

} // namespace talus::detail
