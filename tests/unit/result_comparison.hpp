#pragma once
// Two result directories compared: timeseries.csv column by column and run.h5 frame by frame,
// dataset by dataset, each to a tolerance relative to its own largest magnitude (or exactly).
#include "cli_support.hpp"
#include "talus/io/csv.hpp"
#include "talus/io/results.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace talus::test_support {

/// How one result may differ from another: not at all, or by `relative` of each column's (each
/// dataset's) largest magnitude over the run.
struct Equality {
  double relative = 0;
  /// Columns whose own largest magnitude is no scale (a momentum conserved at zero): the
  /// magnitude to use instead.
  std::map<std::string, double> column_scale{};
  /// Judge each frame's dataset against its largest magnitude over the whole run rather than
  /// in that frame (a field that starts at zero, like stress, is not judged by its round-off
  /// in the first frames).
  bool run_scale = false;
};

inline void expect_same_series(const std::filesystem::path& reference,
                               const std::filesystem::path& resumed, const Equality& eq) {
  if (eq.relative == 0) {
    EXPECT_TRUE(read_file(reference / "timeseries.csv") == read_file(resumed / "timeseries.csv"))
        << "timeseries.csv differs";
    return;
  }
  const talus::CsvTable a = talus::read_csv(reference / "timeseries.csv");
  const talus::CsvTable b = talus::read_csv(resumed / "timeseries.csv");
  ASSERT_EQ(a.rows(), b.rows());
  for (const std::string& name : a.names) {
    const auto& x = a.column(name);
    const auto& y = b.column(name);
    double scale = 0, diff = 0;
    for (std::size_t r = 0; r < x.size(); ++r) {
      scale = std::max(scale, std::abs(x[r]));
      diff = std::max(diff, std::abs(x[r] - y[r]));
    }
    if (const auto given = eq.column_scale.find(name); given != eq.column_scale.end())
      scale = given->second;
    EXPECT_LE(diff, eq.relative * std::max(scale, 1e-300)) << "column " << name;
  }
}

/// Every dataset of every frame, against its largest magnitude in that frame or, with
/// Equality::run_scale, over the run.
inline void expect_same_frames(const std::filesystem::path& reference,
                               const std::filesystem::path& other, const Equality& eq) {
  const talus::ResultsReader a(reference / "run.h5");
  const talus::ResultsReader b(other / "run.h5");
  ASSERT_EQ(a.frame_count(), b.frame_count());
  struct Worst {
    double diff = 0, scale = 0;
  };
  std::map<std::string, double> run_scale;
  std::vector<std::map<std::string, Worst>> frames(static_cast<std::size_t>(a.frame_count()));
  for (Index f = 0; f < a.frame_count(); ++f) {
    EXPECT_EQ(a.frame_step(f), b.frame_step(f));
    // A run whose steps follow the points' speeds (CFL) ends a stage at a time that moves with
    // the points' round-off: the time within the same relative bound (exactly when 0).
    EXPECT_LE(std::abs(a.frame_time(f) - b.frame_time(f)), eq.relative * std::abs(a.frame_time(f)))
        << "frame " << f << " time";
    ASSERT_EQ(a.frame_fields(f), b.frame_fields(f));
    for (const std::string& field : a.frame_fields(f)) {
      Index ra = 0, ca = 0, rb = 0, cb = 0;
      const auto x = a.read(f, field, &ra, &ca);
      const auto y = b.read(f, field, &rb, &cb);
      ASSERT_EQ(x.size(), y.size()) << "frame " << f << " " << field;
      Worst& w = frames[static_cast<std::size_t>(f)][field];
      for (std::size_t i = 0; i < x.size(); ++i) {
        w.scale = std::max(w.scale, std::abs(x[i]));
        w.diff = std::max(w.diff, std::abs(x[i] - y[i]));
      }
      run_scale[field] = std::max(run_scale[field], w.scale);
    }
  }
  for (std::size_t f = 0; f < frames.size(); ++f)
    for (const auto& [field, w] : frames[f]) {
      const double scale = eq.run_scale ? run_scale[field] : w.scale;
      EXPECT_LE(w.diff, eq.relative * scale)
          << "frame " << f << " " << field << ": largest difference " << w.diff << " of " << scale;
    }
}

} // namespace talus::test_support
