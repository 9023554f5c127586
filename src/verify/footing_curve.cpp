#include "footing_curve.hpp"
#include "talus/io/csv.hpp"

#include <algorithm>
#include <fmt/format.h>
#include <fstream>
#include <stdexcept>

namespace talus::verify_cases {

std::size_t FootingCurve::peak() const {
  return static_cast<std::size_t>(std::max_element(pressure.begin(), pressure.end()) -
                                  pressure.begin());
}

FootingCurve load_settlement(const std::filesystem::path& dir, double end_time, double settlement,
                             double pressure_per_force) {
  const CsvTable series = read_csv(dir / "timeseries.csv");
  if (series.rows() == 0) // a curve with nothing measured must fail its rows, not pass them
    throw std::runtime_error(fmt::format("{}: timeseries.csv has no rows", dir.string()));
  const auto& t = series.column("time");
  const auto& step = series.column("step");
  const auto& force = series.column("reaction_footing_y");
  FootingCurve c;
  for (std::size_t k = 0; k < series.rows(); ++k) {
    c.settlement.push_back(settlement * t[k] / end_time);
    c.pressure.push_back(-force[k] * pressure_per_force);
    c.step.push_back(step[k]);
  }
  return c;
}

void write_curve_csv(const std::filesystem::path& file, const FootingCurve& c, double width,
                     double reference_pressure) {
  std::ofstream out(file);
  out << "settlement_m,settlement_over_B,pressure_Pa,pressure_over_reference\n";
  for (std::size_t k = 0; k < c.pressure.size(); ++k)
    out << fmt::format("{:.9g},{:.9g},{:.9g},{:.9g}\n", c.settlement[k], c.settlement[k] / width,
                       c.pressure[k], c.pressure[k] / reference_pressure);
}

} // namespace talus::verify_cases
