// `polydem run --picture` (or [output] picture = true): after the run, rank 0 plots DIR/series.csv
// to DIR/series.png (python_coupling/plots/plot_series.py) and renders a few frames of the HDF5
// snapshots to DIR/frames.png (render_frames.py). A picture is a convenience: when Python, its
// packages or the script are missing, or the run wrote no HDF5 snapshots, polydem warns and the
// run still succeeds.
#pragma once

#include <string>

namespace polydem::app {

/// Runs render_frames.py on `out_dir` and waits for it; returns the PNG written, or "" after a
/// warning saying why there is none. Call on one rank.
std::string renderPicture(const std::string& out_dir);

/// Runs plot_series.py on `out_dir` (its series.csv) and waits for it; returns the PNG written,
/// or "" after a warning saying why there is none. Call on one rank.
std::string plotSeries(const std::string& out_dir);

}  // namespace polydem::app
