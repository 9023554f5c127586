#pragma once
// `talus render`: PNG pictures of a run's frames, deformed voxels (or dots) coloured by a
// particle field or a colour pattern, with a colour bar, axes in model units and the time. A 3D
// run is drawn as a plane slice (--slice) or as its outer voxel faces seen from --view.
// The request is validated here against run.h5 (bad input: InputError naming the option, exit 2,
// nothing written); the drawing is matplotlib's (scripts/render.py), which brings colour maps,
// colour bars and axes that a raw drawing library (cairo) would need written by hand.
#include <filesystem>
#include <string>
#include <vector>

namespace talus {

struct RenderOptions {
  std::filesystem::path results; ///< run.h5
  std::string field;             ///< particle dataset, e.g. "stress", "stress_smoothed"
  std::string component;         ///< "xy", "x", "magnitude", ...; empty for scalar fields
  std::string frame = "last";    ///< frame number, "last" or "all"
  std::string pattern;           ///< "checker", "stripes_horizontal" or "stripes_vertical"
  std::string mode;              ///< "voxels" or "points"; empty: voxels when written
  std::string slice;             ///< 3D only: "z=0.5" (x, y or z); empty: the outer-face view
  /// 3D outer-face view: "iso", "x", "y" or "z"; empty (and no slice): the slice z = const
  /// through the point that moved the most, which shows what changed
  std::string view;
  std::vector<double> clim;     ///< the colour range {lo, hi}; empty: the values' range
  bool log = false;             ///< a logarithmic colour scale
  std::vector<double> crop;     ///< {x0, y0, x1, y1} of the picture's axes; empty: everything
  bool delta = false;           ///< colour by the change since frame 0
  std::filesystem::path output; ///< OUT.png; with frame "all": OUT_000000.png, ...
};

/// Validates the request, then draws; returns the exit code (0).
int render(const RenderOptions& options);

} // namespace talus
