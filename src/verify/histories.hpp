#pragma once
// Time histories (or profiles) that verification cases plot in their report figure: one CSV of
// (panel, series, x, y) rows drawn by scripts/plot_stability.py, one subplot per panel.
#include "talus/io/csv.hpp"

#include <filesystem>
#include <string>
#include <vector>

namespace talus::verify_cases {

struct History {
  std::string panel;  ///< subplot title, e.g. "E(t) / E(0) - 1"
  std::string series; ///< legend entry, e.g. "CFL 0.5"
  std::vector<double> x, y;
};

class HistoryPlot {
public:
  /// `log_panels`: panels whose vertical axis is logarithmic (absolute values are plotted);
  /// `x_label`: the horizontal axis's label (a profile plots against depth, not time).
  explicit HistoryPlot(std::vector<std::string> log_panels = {}, std::string x_label = "t [s]")
      : log_panels_(std::move(log_panels)), x_label_(std::move(x_label)) {}
  void add(History h) { histories_.push_back(std::move(h)); }
  /// Adds `column` of a timeseries against time, transformed by y -> (y / y(0) - 1) when
  /// `relative` (energy histories).
  void add_column(const std::string& panel, const std::string& series, const CsvTable& table,
                  const std::string& column, bool relative);
  /// Writes `<dir>/<name>_histories.csv` and draws `<dir>/<name>.png` titled `title`.
  void write(const std::filesystem::path& dir, const std::string& name,
             const std::string& title) const;

private:
  std::vector<std::string> log_panels_;
  std::string x_label_;
  std::vector<History> histories_;
};

} // namespace talus::verify_cases
