// `polydem run --picture` (or [output] picture = true): after the run, rank 0 plots DIR/series.csv
// to DIR/series.png (python_coupling/plots/plot_series.py) and renders a few frames of the HDF5
// snapshots to DIR/frames.png (render_frames.py): the free blocks coloured by speed,
// displacement or joint, seen from the slope's face unless an azimuth is chosen. A picture is a
// convenience: when Python, its packages or the script are missing, or the run wrote no HDF5
// snapshots, polydem warns and the run still succeeds.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace polydem::app {

/// What the frames show and from where (render_frames.py's --field and --azimuth).
struct PictureOptions {
  std::string field = "speed";    // speed, displacement or joint (pictureFields())
  std::optional<double> azimuth;  // view azimuth [deg]; unset: from the slope's face
};

/// The fields the frames can be coloured by: speed, displacement, joint.
const std::vector<std::string>& pictureFields();

/// Runs render_frames.py on `out_dir` and waits for it; returns the PNG written, or "" after a
/// warning saying why there is none. Call on one rank.
std::string renderPicture(const std::string& out_dir, const PictureOptions& options = {});

/// Runs plot_series.py on `out_dir` (its series.csv) and waits for it; returns the PNG written,
/// or "" after a warning saying why there is none. Call on one rank.
std::string plotSeries(const std::string& out_dir);

/// Runs plot_thickness.py on `out_dir` (its thickness.csv, as `polydem runout` writes it) and
/// waits for it; returns the PNG written (thickness.png), or "" after a warning. One rank.
std::string plotThickness(const std::string& out_dir);
/// Runs plot_realizations.py on `out_dir` (realizations.csv, realizations.json) and waits for it:
/// DIR/realizations.png, the histogram and the CDF of F; "" after a warning when there is none.
std::string plotRealizations(const std::string& out_dir);

}  // namespace polydem::app
