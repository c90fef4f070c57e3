// From failure to deposit: a failing slope run on at the scene's own strengths until its blocks
// are at rest, and the deposit it leaves measured (`polydem runout`, `polydem fos --runout`).
//
// The run-on uses the scene as written: its strengths unreduced, its own damping (the static
// solution's local damping of the fos trials would brake a dynamic runout), and each joint's own
// law, so that a `coulomb-residual` joint whose sub-contacts slipped during the failure carries
// on at its residual strength (its history says so) and a Barton-Bandis joint at its mobilized
// one. It is checked on the steps that are multiples of check_every:
//   at rest  every free block's speed, |v| + |w| R at its farthest point, is below
//            kRestSpeed sqrt(g s) (s = V^(1/3) its size: a Froude number, free of the length
//            scale) at kRestChecks checks in a row;
//   capped   otherwise at time_cap of run-on, reported as not at rest.
// Measures at the end, from the blocks' poses at the scene's start (runout_deposit.cpp):
//   - the failed mass: the free blocks whose centroid moved at least kMovedFraction of their size;
//   - the direction of travel: the horizontal unit vector of the failed mass's summed
//     displacement (the slope's dip direction for a slide; stated in the output);
//   - runout distance: the farthest point of the failed mass along that direction now, minus the
//     farthest (its toe) at the start: how far the front travelled, horizontally;
//   - largest block travel: the longest centroid displacement of a free block;
//   - the thickness map on a horizontal grid of square cells (cell kCellFraction of the failed
//     mass's median block size unless given; grid lines on multiples of it): at a point, the top
//     of the failed blocks' vertical extent minus the top of the ground (the fixed bodies and the
//     free blocks that did not move) under it, from each convex block's face planes; a cell's
//     thickness is the mean over 4 x 4 points of it, so that the map integrates to the failed
//     volume. Cells thicker than kThinFraction of the cell size form the deposit: its area, its
//     length along the direction of travel and width across it, and its volume.
// Restartable: a checkpoint (DIR/runout.h5, replaced atomically) every checkpoint_every steps and
// on SIGTERM/SIGUSR1 stores the state and the run-on's counters; continuing from it gives the
// same bits as a run-on that never stopped, on any rank count.
#pragma once

#include <mpi.h>

#include <cstdint>
#include <string>
#include <vector>

#include "polydem/core/types.h"
#include "polydem/setup/setup.h"

namespace polydem::sim {
class Simulation;
}  // namespace polydem::sim

namespace polydem::run {

/// At rest: every free block's speed below this fraction of sqrt(g s) ...
constexpr double kRestSpeed = 1e-4;
/// ... at this many checks in a row.
constexpr int kRestChecks = 3;
/// A block belongs to the failed mass when its centroid moved this fraction of its size.
constexpr double kMovedFraction = 0.1;
/// The default cell of the thickness map: this fraction of the failed mass's median block size.
constexpr double kCellFraction = 0.25;
/// A cell is part of the deposit when its thickness exceeds this fraction of the cell size.
constexpr double kThinFraction = 1e-3;

struct RunoutSettings {
  double time_cap = 0.0;               // s of run-on
  std::int64_t check_every = 100;      // steps
  double cell = 0.0;                   // m; 0: kCellFraction of the median block size
  std::int64_t checkpoint_every = 0;   // steps; 0: only on a stop signal
  std::string dir;                     // where runout.h5 goes
  std::string scene_text, scene_file;  // stored in the checkpoint
};

/// The run-on's counters, as a checkpoint keeps them.
struct RunoutProgress {
  double start_time = 0.0;  // s, simulation time when the run-on began
  int rest_checks = 0;      // consecutive checks at rest so far
};

struct ThicknessCell {
  int i = 0, j = 0;                // column (x) and row (y) of the grid
  double x = 0.0, y = 0.0;         // m, the cell's centre
  double ground = 0.0, top = 0.0;  // m, the ground's and the failed mass's top there
  bool has_ground = false;         // a fixed body or standing block lies under the centre
  double thickness = 0.0;          // m, top - ground (>= 0)
};

struct RunoutDeposit {
  int failed_blocks = 0, free_blocks = 0;
  double failed_volume = 0.0;               // m^3, of the failed blocks
  Vec3 direction = Vec3::UnitX();           // horizontal unit vector of travel
  double toe_start = 0.0, front_end = 0.0;  // m, along `direction`
  double runout = 0.0;                      // m, front_end - toe_start
  double max_travel = 0.0;                  // m, the largest centroid displacement
  Uid max_travel_uid = 0;
  double cell = 0.0;                             // m
  double area = 0.0, length = 0.0, width = 0.0;  // m^2, m, m
  double volume = 0.0;                           // m^3, the thickness map integrated
  double max_thickness = 0.0;                    // m
  double x0 = 0.0, y0 = 0.0;                     // m, the grid's lower corner
  int nx = 0, ny = 0;
  std::vector<ThicknessCell> cells;  // the cells with a failed block over them
};

struct RunoutSample {
  double time = 0.0;               // s of run-on
  double mean_displacement = 0.0;  // m, of the free blocks from the scene's start
  double mean_speed = 0.0;         // m/s
  double speed_ratio = 0.0;        // the largest |v| / sqrt(g s)
};

struct RunoutResult {
  bool at_rest = false;
  std::string stopped_by;        // "rest", "time_cap" or a signal name
  double time = 0.0;             // s of run-on
  std::int64_t steps = 0;        // the simulation's step count at the end
  double max_speed_ratio = 0.0;  // the largest |v| / sqrt(g s) at the end
  std::uint64_t state_hash = 0;
  std::string checkpoint;            // the checkpoint written on a stop signal, if any
  std::vector<RunoutSample> series;  // every check of this part of the run-on
  RunoutDeposit deposit;
};

/// The largest speed ratio (|v| + |w| R) / sqrt(g s) over the free blocks (collective).
double largestSpeedRatio(const sim::Simulation& sim);

/// The deposit measures of the current state (collective; every rank gets them). `cell`: the
/// grid's cell size, 0 for the default.
RunoutDeposit measureDeposit(const sim::Simulation& sim, double cell);

/// Runs `sim` on until at rest or settings.time_cap after progress.start_time (collective),
/// checkpointing as the settings say, then measures the deposit. A stop signal ends it after the
/// current step with a checkpoint (stopped_by the signal's name, not at rest).
RunoutResult runRunout(sim::Simulation& sim, const RunoutSettings& settings,
                       RunoutProgress progress);

/// The run-on's counters and settings as the run_state JSON of its checkpoint, and back: the
/// settings a continued run-on must keep to give the same bits (time_cap, check_every, cell,
/// checkpoint_every) are read into `settings`. Throws CheckpointError naming `file` if missing.
std::string runoutStateJson(const RunoutProgress& progress, const RunoutSettings& settings,
                            const setup::Setup& scene);
RunoutProgress runoutStateFrom(const std::string& json, const std::string& file,
                               RunoutSettings& settings);

/// The thickness map as CSV: i,j,x,y,ground,top,thickness per cell with a failed block over it.
std::string thicknessCsv(const RunoutDeposit& d);

}  // namespace polydem::run
