#pragma once
// The load-settlement curve of a footing verification (strip, circular): the footing pressure
// from the prescribed region's reaction at every row of timeseries.csv, its peak, and the CSV
// that scripts/plot_footing.py draws (Newton iterations: newton_log.hpp).
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace talus::verify_cases {

struct FootingCurve {
  std::vector<double> settlement, pressure, step;
  std::size_t peak() const; ///< the row of the largest pressure
};

/// The curve of a run whose prescribed region `footing` settles by `settlement` over
/// `end_time`; the pressure is pressure_per_force times -reaction_footing_y. Throws
/// std::runtime_error when the run wrote no row (nothing measured).
FootingCurve load_settlement(const std::filesystem::path& dir, double end_time, double settlement,
                             double pressure_per_force);

/// Columns settlement_m, settlement_over_B, pressure_Pa, pressure_over_reference (B the
/// footing's width or diameter).
void write_curve_csv(const std::filesystem::path& file, const FootingCurve& c, double width,
                     double reference_pressure);

} // namespace talus::verify_cases
