// case_differences (include/talus/io/case_reader.hpp): the two cases' YAML trees, each with
// its overrides applied, compared key by key.
#include "talus/io/case_reader.hpp"

#include "yaml_support.hpp"

#include <fmt/format.h>
#include <set>
#include <yaml-cpp/yaml.h>

namespace talus {

namespace {

YAML::Node tree_of(const std::string& text, const std::vector<std::string>& overrides) {
  const std::vector<YAML::Node> documents = YAML::LoadAll(text);
  YAML::Node root = documents.empty() ? YAML::Node() : documents.front();
  detail::apply_overrides(root, overrides);
  return root;
}

std::string child(const std::string& path, const std::string& key) {
  return path.empty() ? key : path + "." + key;
}

void compare(const YAML::Node& a, const YAML::Node& b, const std::string& path,
             std::vector<std::string>& out) {
  if (a.Type() != b.Type()) {
    out.push_back(path);
    return;
  }
  switch (a.Type()) {
  case YAML::NodeType::Map: {
    std::set<std::string> keys;
    for (const auto& kv : a)
      keys.insert(kv.first.Scalar());
    for (const auto& kv : b)
      keys.insert(kv.first.Scalar());
    for (const std::string& k : keys) {
      const YAML::Node x = a[k], y = b[k];
      if (!x.IsDefined() || !y.IsDefined())
        out.push_back(child(path, k));
      else
        compare(x, y, child(path, k), out);
    }
    break;
  }
  case YAML::NodeType::Sequence:
    for (std::size_t i = 0; i < std::max(a.size(), b.size()); ++i) {
      const std::string item = fmt::format("{}[{}]", path, i);
      if (i >= a.size() || i >= b.size())
        out.push_back(item);
      else
        compare(a[i], b[i], item, out);
    }
    break;
  case YAML::NodeType::Scalar:
    if (a.Scalar() != b.Scalar())
      out.push_back(path);
    break;
  default:
    break;
  }
}

} // namespace

std::vector<std::string> case_differences(const std::string& text_a,
                                          const std::vector<std::string>& overrides_a,
                                          const std::string& text_b,
                                          const std::vector<std::string>& overrides_b) {
  std::vector<std::string> out;
  compare(tree_of(text_a, overrides_a), tree_of(text_b, overrides_b), "", out);
  return out;
}

} // namespace talus
