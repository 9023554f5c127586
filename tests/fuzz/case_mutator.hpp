#pragma once
// The seeded mutator of talus_fuzz_case_reader (fuzz_case_reader.cpp): each mutant is a shipped
// case with 1 to 4 edits (byte flips, token swaps, deleted, duplicated and swapped lines, numbers
// replaced by extremes, huge strings, deep nesting, YAML tags, stray YAML syntax, lines of other
// cases, changed line ends), plus sometimes --set overrides with odd values. The same seed gives
// the same sequence of mutants.
#include <cctype>
#include <cstring>
#include <random>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace talus::fuzz {

class Mutator {
public:
  Mutator(std::uint64_t seed, std::vector<std::string> seeds)
      : random_(seed), seeds_(std::move(seeds)) {}

  std::string mutant() {
    std::string text = seeds_[pick(seeds_.size())];
    const std::size_t edits = 1 + pick(4);
    for (std::size_t k = 0; k < edits; ++k)
      mutate(text);
    return text;
  }

  /// A few --set overrides for some inputs: real keys with odd values, odd keys.
  std::vector<std::string> overrides() {
    std::vector<std::string> out;
    if (pick(8) != 0)
      return out;
    static const char* keys[] = {"grid.cell_size",
                                 "grid.extent",
                                 "time.dt",
                                 "time.cfl",
                                 "bodies[0].velocity",
                                 "materials[0].youngs_modulus",
                                 "bodies.0.min",
                                 "solver.shape",
                                 "probes[0].point",
                                 "output.every_steps",
                                 "name",
                                 "stages[0].time.dt",
                                 "bodies[0].split.alpha",
                                 "a.b[3].c"};
    const std::size_t n = 1 + pick(2);
    for (std::size_t i = 0; i < n; ++i)
      out.push_back(std::string(keys[pick(std::size(keys))]) + "=" + odd_value());
    if (pick(10) == 0)
      out.push_back("no equals sign");
    return out;
  }

private:
  std::size_t pick(std::size_t n) { return n == 0 ? 0 : static_cast<std::size_t>(random_() % n); }

  std::string odd_value() {
    static const char* values[] = {"0",
                                   "-1",
                                   "1e308",
                                   "-1e308",
                                   "nan",
                                   ".inf",
                                   "-.inf",
                                   "1e-308",
                                   "9e15",
                                   "1e15",
                                   "4294967296",
                                   "[1e308, 1e308]",
                                   "[0, 0]",
                                   "[]",
                                   "{}",
                                   "~",
                                   "\"\"",
                                   "!weird 1",
                                   "!!binary AA==",
                                   "1\n---\nx: 1",
                                   "\"open",
                                   "[[[[1]]]]",
                                   "\xff\xfe",
                                   "1e-9",
                                   "[-1e9, 1e9]",
                                   "true",
                                   "usl",
                                   "'a,b'",
                                   "&a 1",
                                   "*a"};
    std::string v = values[pick(std::size(values))];
    if (pick(20) == 0)
      v = std::string(1 + pick(100000), 'x'); // one argument holds at most 128 kB
    return v;
  }

  std::vector<std::size_t> line_starts(const std::string& text) {
    std::vector<std::size_t> starts{0};
    for (std::size_t i = 0; i < text.size(); ++i)
      if (text[i] == '\n' && i + 1 < text.size())
        starts.push_back(i + 1);
    return starts;
  }

  /// [begin, end) of a random line (without its '\n').
  std::pair<std::size_t, std::size_t> random_line(const std::string& text) {
    const auto starts = line_starts(text);
    const std::size_t b = starts[pick(starts.size())];
    std::size_t e = text.find('\n', b);
    if (e == std::string::npos)
      e = text.size();
    return {b, e};
  }

  /// [begin, end) of a random number in the text, if any.
  bool random_number(const std::string& text, std::size_t& b, std::size_t& e) {
    std::vector<std::pair<std::size_t, std::size_t>> numbers;
    for (std::size_t i = 0; i < text.size(); ++i) {
      const bool start = std::isdigit(static_cast<unsigned char>(text[i])) &&
                         (i == 0 || std::strchr(" [,:-", text[i - 1]) != nullptr);
      if (!start)
        continue;
      std::size_t j = i;
      while (j < text.size() && std::strchr("0123456789.eE+-", text[j]) != nullptr)
        ++j;
      numbers.emplace_back(i, j);
      i = j;
    }
    if (numbers.empty())
      return false;
    std::tie(b, e) = numbers[pick(numbers.size())];
    return true;
  }

  /// [begin, end) of a random scalar value after "key: ".
  bool random_value(const std::string& text, std::size_t& b, std::size_t& e) {
    for (int attempt = 0; attempt < 8; ++attempt) {
      const auto [lb, le] = random_line(text);
      const std::size_t colon = text.find(": ", lb);
      if (colon == std::string::npos || colon >= le)
        continue;
      b = colon + 2;
      e = le;
      const std::size_t comment = text.find(" #", b);
      if (comment != std::string::npos && comment < e)
        e = comment;
      if (b < e)
        return true;
    }
    return false;
  }

  void mutate(std::string& text) {
    if (text.empty()) {
      text = seeds_[pick(seeds_.size())];
      return;
    }
    std::size_t b = 0, e = 0;
    switch (pick(13)) {
    case 0: { // byte flip
      const std::size_t at = pick(text.size());
      text[at] =
          pick(2) ? static_cast<char>(text[at] ^ (1 << pick(8))) : static_cast<char>(pick(256));
      break;
    }
    case 1: { // swap two tokens
      std::vector<std::pair<std::size_t, std::size_t>> tokens;
      for (std::size_t i = 0; i < text.size();) {
        while (i < text.size() && std::strchr(" \n[]{},:", text[i]) != nullptr)
          ++i;
        std::size_t j = i;
        while (j < text.size() && std::strchr(" \n[]{},:", text[j]) == nullptr)
          ++j;
        if (j > i)
          tokens.emplace_back(i, j);
        i = j;
      }
      if (tokens.size() < 2)
        break;
      auto x = tokens[pick(tokens.size())], y = tokens[pick(tokens.size())];
      if (x.first > y.first)
        std::swap(x, y);
      if (x.second > y.first)
        break;
      const std::string a = text.substr(x.first, x.second - x.first);
      const std::string c = text.substr(y.first, y.second - y.first);
      text.replace(y.first, c.size(), a);
      text.replace(x.first, a.size(), c);
      break;
    }
    case 2: { // delete a line
      std::tie(b, e) = random_line(text);
      text.erase(b, std::min(text.size(), e + 1) - b);
      break;
    }
    case 3: { // duplicate a line
      std::tie(b, e) = random_line(text);
      text.insert(e, "\n" + text.substr(b, e - b));
      break;
    }
    case 4: { // swap two lines
      const auto [b1, e1] = random_line(text);
      const auto [b2, e2] = random_line(text);
      if (b1 == b2 || (b1 < b2 && e1 >= b2) || (b2 < b1 && e2 >= b1))
        break;
      const std::string l1 = text.substr(b1, e1 - b1), l2 = text.substr(b2, e2 - b2);
      if (b1 < b2) {
        text.replace(b2, l2.size(), l1);
        text.replace(b1, l1.size(), l2);
      } else {
        text.replace(b1, l1.size(), l2);
        text.replace(b2, l2.size(), l1);
      }
      break;
    }
    case 5:
    case 6: { // a number becomes an extreme
      if (!random_number(text, b, e))
        break;
      static const char* extremes[] = {"0",    "-1",     "1e308", "-1e308", "nan",
                                       ".nan", ".inf",   "-.inf", "1e-308", "5e-324",
                                       "9e15", "1e15",   "1e400", "-0",     "4294967296",
                                       "1e-9", "100000", "0x10",  "1_000",  "2.5"};
      std::string v = extremes[pick(std::size(extremes))];
      if (pick(10) == 0)
        v = "1" + std::string(1 + pick(5000), '0');
      text.replace(b, e - b, v);
      break;
    }
    case 7: { // a value becomes a huge string
      if (!random_value(text, b, e))
        break;
      text.replace(b, e - b, std::string(1 + pick(pick(2) ? 2000 : 1000000), 'a' + pick(26)));
      break;
    }
    case 8: { // deep nesting as a value
      if (!random_value(text, b, e))
        break;
      const std::size_t depth = 1 + pick(pick(2) ? 80 : 700);
      const bool map = pick(2) != 0;
      std::string v;
      for (std::size_t i = 0; i < depth; ++i)
        v += map ? "{a: " : "[";
      v += "1";
      for (std::size_t i = 0; i < depth; ++i)
        v += map ? "}" : "]";
      text.replace(b, e - b, v);
      break;
    }
    case 9: { // a YAML tag before a value
      if (!random_value(text, b, e))
        break;
      static const char* tags[] = {"!weird ", "!!binary ", "!!str ", "!!int ",   "!!float ",
                                   "!!map ",  "!!seq ",    "! ",     "!<tag:x> "};
      text.insert(b, tags[pick(std::size(tags))]);
      break;
    }
    case 10: { // stray YAML syntax
      static const char* bits[] = {
          "\"",      "'",           "\r",           "\t", "(NUL)", "\xff",
          "\n---\n", "&a ",         "*a",           "? ", "{",     "[",
          "]",       "}",           ": ",           "- ", "#",     "|",
          ">",       "%YAML 1.2\n", "\xef\xbb\xbf", "\\", ",",     "<<: *a\n"};
      const std::size_t at = pick(text.size() + 1);
      const std::size_t which = pick(std::size(bits));
      if (which == 4)
        text.insert(at, 1, '\0');
      else
        text.insert(at, bits[which]);
      break;
    }
    case 11: { // a line of another case
      const std::string& other = seeds_[pick(seeds_.size())];
      const auto [ob, oe] = random_line(other);
      std::tie(b, e) = random_line(text);
      text.insert(b, other.substr(ob, oe - ob) + "\n");
      break;
    }
    case 12: { // line ends
      if (pick(2)) {
        for (char& c : text)
          if (c == '\n')
            c = '\r';
      } else {
        std::string crlf;
        for (char c : text) {
          if (c == '\n')
            crlf += '\r';
          crlf += c;
        }
        text = crlf;
      }
      break;
    }
    }
    if (text.size() > 8000000)
      text.resize(8000000);
  }

  std::mt19937_64 random_;
  std::vector<std::string> seeds_;
};

} // namespace talus::fuzz
