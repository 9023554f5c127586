#include "histories.hpp"

#include "talus/post/python_script.hpp"

#include <fmt/format.h>
#include <fstream>

namespace talus::verify_cases {

void HistoryPlot::add_column(const std::string& panel, const std::string& series,
                             const CsvTable& table, const std::string& column, bool relative) {
  History h{panel, series, table.column("time"), table.column(column)};
  if (relative) {
    const double first = h.y.front();
    for (double& v : h.y)
      v = v / first - 1.0;
  }
  add(std::move(h));
}

void HistoryPlot::write(const std::filesystem::path& dir, const std::string& name,
                        const std::string& title) const {
  const auto csv = dir / (name + "_histories.csv");
  std::ofstream out(csv);
  out << "panel,series,x,y\n";
  for (const auto& h : histories_)
    for (std::size_t k = 0; k < h.x.size(); ++k)
      out << fmt::format("\"{}\",\"{}\",{:.10g},{:.10g}\n", h.panel, h.series, h.x[k], h.y[k]);
  out.close();
  std::vector<std::string> args = {"--x-label", x_label_, csv.string(),
                                   (dir / (name + ".png")).string(), title};
  args.insert(args.end(), log_panels_.begin(), log_panels_.end());
  run_python_script("plot_stability.py", args);
}

} // namespace talus::verify_cases
