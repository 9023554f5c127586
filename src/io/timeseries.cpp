// TimeSeriesWriter: timeseries.csv, one header line and one row of doubles per call, each row
// flushed so that a killed run keeps everything appended so far (docs/output-format.md).
#include "talus/io/results.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>

namespace talus {

TimeSeriesWriter::TimeSeriesWriter(const std::filesystem::path& file,
                                   std::vector<std::string> columns, bool append)
    : columns_(columns.size()) {
  if (columns.empty())
    throw std::invalid_argument("TimeSeriesWriter: '" + file.string() +
                                "' needs at least one column");
  for (const auto& c : columns)
    if (c.empty() || c.find_first_of(",\"\r\n") != std::string::npos)
      throw std::invalid_argument("TimeSeriesWriter: column name '" + c + "' for '" +
                                  file.string() +
                                  "' must be non-empty and contain no comma, quote or newline");
  file_ = std::fopen(file.c_str(), append ? "a" : "w");
  if (!file_)
    throw std::runtime_error("cannot create time series file '" + file.string() +
                             "': " + std::strerror(errno));
  if (append)
    return;
  std::string header;
  for (std::size_t i = 0; i < columns.size(); ++i) {
    if (i)
      header += ',';
    header += columns[i];
  }
  header += '\n';
  if (std::fputs(header.c_str(), file_) < 0 || std::fflush(file_) != 0) {
    const std::string why = std::strerror(errno);
    std::fclose(file_);
    file_ = nullptr;
    throw std::runtime_error("cannot write time series file '" + file.string() + "': " + why);
  }
}

TimeSeriesWriter::~TimeSeriesWriter() {
  if (file_)
    std::fclose(file_);
}

void TimeSeriesWriter::append(const std::vector<double>& row) {
  if (row.size() != columns_)
    throw std::invalid_argument("TimeSeriesWriter::append: row has " + std::to_string(row.size()) +
                                " values, the header has " + std::to_string(columns_) + " columns");
  if (!file_)
    return;
  std::string line;
  char buf[40];
  for (std::size_t i = 0; i < row.size(); ++i) {
    if (i)
      line += ',';
    std::snprintf(buf, sizeof buf, "%.17g", row[i]);
    line += buf;
  }
  line += '\n';
  if (std::fputs(line.c_str(), file_) < 0 || std::fflush(file_) != 0)
    throw std::runtime_error(std::string("cannot append to time series file: ") +
                             std::strerror(errno));
}

} // namespace talus
