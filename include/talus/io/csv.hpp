#pragma once
// Reads a numeric CSV with one header line (timeseries.csv) into named columns.
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace talus {

struct CsvTable {
  std::vector<std::string> names;
  std::map<std::string, std::vector<double>> columns;
  const std::vector<double>& column(const std::string& name) const;
  std::size_t rows() const { return columns.empty() ? 0 : columns.begin()->second.size(); }
};

CsvTable read_csv(const std::filesystem::path& file);

} // namespace talus
