#include "talus/core/errors.hpp"

#include <fmt/format.h>

namespace talus {

std::string SourceLocation::to_string() const {
  std::string s = file.empty() ? std::string("<input>") : file;
  if (line > 0)
    s = column > 0 ? fmt::format("{}:{}:{}", s, line, column) : fmt::format("{}:{}", s, line);
  // A key path holds what the user typed: a 5 MB key must not become a 5 MB message.
  constexpr std::size_t kShownKey = 200;
  if (!key_path.empty())
    s = fmt::format("{}: key '{}'", s,
                    key_path.size() > kShownKey ? key_path.substr(0, kShownKey) + "..." : key_path);
  return s;
}

InputError::InputError(SourceLocation where, const std::string& what)
    : std::runtime_error(fmt::format("{}: {}", where.to_string(), what)), where_(std::move(where)),
      detail_(what) {}

} // namespace talus
