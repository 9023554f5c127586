#include "talus/io/csv.hpp"

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace talus {

const std::vector<double>& CsvTable::column(const std::string& name) const {
  const auto it = columns.find(name);
  if (it == columns.end())
    throw std::runtime_error("CSV has no column '" + name + "'");
  return it->second;
}

CsvTable read_csv(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in)
    throw std::runtime_error("cannot open " + file.string());
  CsvTable t;
  std::string line;
  if (!std::getline(in, line))
    throw std::runtime_error(file.string() + " is empty");
  std::stringstream header(line);
  for (std::string name; std::getline(header, name, ',');)
    t.names.push_back(name);
  std::vector<std::vector<double>> data(t.names.size());
  while (std::getline(in, line)) {
    if (line.empty())
      continue;
    std::stringstream row(line);
    std::size_t c = 0;
    for (std::string cell; std::getline(row, cell, ','); ++c) {
      if (c >= data.size())
        throw std::runtime_error(file.string() + ": row longer than the header");
      char* end = nullptr;
      const double value = std::strtod(cell.c_str(), &end); // accepts subnormals, unlike stod
      if (end == cell.c_str())
        throw std::runtime_error(file.string() + ": '" + cell + "' is not a number");
      data[c].push_back(value);
    }
    if (c != data.size())
      throw std::runtime_error(file.string() + ": row shorter than the header");
  }
  for (std::size_t c = 0; c < t.names.size(); ++c)
    t.columns[t.names[c]] = std::move(data[c]);
  return t;
}

} // namespace talus
