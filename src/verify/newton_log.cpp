#include "newton_log.hpp"

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

double worst_newton_order(const std::filesystem::path& log, double floor) {
  std::ifstream in(log);
  std::string line;
  double worst = 1e300;
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
        worst = std::min(worst, std::log(r[k + 1]) / std::log(r[k]));
  }
  return worst;
}

} // namespace talus::verify_cases
