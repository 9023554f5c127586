#include "newton_log.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

namespace talus::verify_cases {

std::vector<int> newton_iterations(const std::filesystem::path& dir, double last_step) {
  std::ifstream log(dir / "newton.log");
  std::vector<int> its;
  std::string line;
  while (std::getline(log, line)) {
    if (line.empty() || line[0] == '#')
      continue;
    std::istringstream in(line);
    double step = 0, t_end = 0, dt = 0;
    std::string converged;
    int iterations = 0;
    in >> step >> t_end >> dt >> converged >> iterations;
    if (converged == "yes" && step <= last_step)
      its.push_back(iterations);
  }
  return its;
}

std::optional<double> worst_newton_order(const std::filesystem::path& log, double floor) {
  std::ifstream in(log);
  std::string line;
  std::optional<double> worst;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#')
      continue;
    // After '|': the residual history, preceded by an abandoned attempt in [...] if any.
    auto start = line.find('|');
    if (const auto bracket = line.find(']', start); bracket != std::string::npos)
      start = bracket;
    std::istringstream values(line.substr(start + 1));
    std::vector<double> r;
    for (double v; values >> v;)
      r.push_back(v);
    for (std::size_t k = 0; k + 1 < r.size(); ++k)
      if (r[k] < 1e-2 && r[k + 1] > floor)
        worst = std::min(worst.value_or(HUGE_VAL), std::log(r[k + 1]) / std::log(r[k]));
  }
  return worst;
}

Check newton_order_check(std::string quantity, const std::filesystem::path& log, double lower,
                         std::string note) {
  if (const std::optional<double> order = worst_newton_order(log))
    return at_least_check(std::move(quantity), *order, lower, std::move(note));
  return holds_check(std::move(quantity), false,
                     fmt::format("nothing measured: no residual pair below 1e-2 and above the "
                                 "round-off floor in {}",
                                 log.string()));
}

Check newton_iterations_check(std::string quantity, std::vector<int> iterations, double quantile,
                              double upper, std::string note) {
  if (iterations.empty())
    return holds_check(std::move(quantity), false, "nothing measured: no converged load step");
  std::sort(iterations.begin(), iterations.end());
  const auto k =
      static_cast<std::size_t>(quantile * static_cast<double>(iterations.size() - 1) + 0.5);
  return at_most_check(std::move(quantity), iterations[k], upper, std::move(note));
}

} // namespace talus::verify_cases
