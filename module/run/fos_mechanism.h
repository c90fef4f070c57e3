// The mechanism of a slope's failure, as `polydem fos` shows it: the failed trial just above the
// factor of safety (the smallest failed F: strengths just below the critical ones) is run again,
// with snapshots, the same bits as in the search up to its decision, and then on for one more
// window (settle_time), or until a block has moved kRunOnFraction of its size, or time_cap.
// Measured over that run-on, from the state at the decision (the trial is failing there, and the
// elastic settling of its first moments is over) to the end:
//   - each free block's displacement d (centroid) and rotation theta, and its reach |d| + theta R
//     (R its circumradius: no point of the block moved further); the block moves when its reach
//     is at least kMoveShare of the largest reach of any block and kRestFraction of its size
//     (below that it is noise, not motion). A trial just above the critical
//     strength may only creep (millimetres on metre blocks): the mechanism is the pattern of that
//     motion, whatever its size;
//   - each touching contact's slip: the tangential part of the relative displacement of the two
//     blocks' material points at the contact point, from their poses at the decision and the end;
//     a contact slips when its slip is at least kMoveShare of the largest slip (and
//     kRestFraction of the smaller block's size);
//   - the slip summed per interaction (the [[joint]] the contact takes, or its material pair):
//     the governing interaction is the one with the largest total slip (none if no contact
//     slips);
//   - each moving block's mode: falling (no contact at the end), else toppling when rotation
//     carries it (theta R > kRotationShare |d|) and its seat (the contact whose normal is
//     nearest the vertical) slips less than kPivotSlipShare |d| (it pivots on that edge),
//     rotating when rotation carries it and the seat slips, sliding otherwise.
// Every figure is a ratio to block sizes or to the mechanism's own largest motion: free of the
// scene's length scale.
#pragma once

#include <mpi.h>

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "polydem/core/types.h"
#include "polydem/run/fos.h"
#include "polydem/setup/setup.h"

namespace polydem::run {

/// A block moves (a contact slips) when its reach (slip) is at least this share of the largest,
constexpr double kMoveShare = 0.1;
/// and at least this fraction of its size (the smaller block's, for a contact): below it the
/// motion is round-off and elastic noise, not a mechanism.
constexpr double kRestFraction = 1e-5;
/// The run-on ends early once some block has moved this fraction of its size V^(1/3).
constexpr double kRunOnFraction = 0.1;
/// Rotation carries a block when theta R exceeds this fraction of its centroid's displacement.
constexpr double kRotationShare = 0.5;
/// A rotating block topples (pivots) when its seat slipped less than this fraction of |d|.
constexpr double kPivotSlipShare = 0.5;
/// Snapshots of the mechanism: one every max_time / kSnapshotsPerMaxTime of simulated time.
constexpr int kSnapshotsPerMaxTime = 10;

struct FosBlockMotion {
  Uid uid = 0;
  std::string label;
  Vec3 displacement = Vec3::Zero();  // m, of the centroid from the decision to the end
  double rotation_deg = 0.0;         // angle of the rotation from the decision to the end
  double size = 0.0;                 // m, V^(1/3)
  double reach = 0.0;                // m, |d| + theta R
  int contacts = 0;                  // touching contacts at the end
  double seat_slip = 0.0;            // m, slip of the contact nearest the vertical
  std::string mode;                  // sliding, toppling, rotating, falling; "" if it stays
};

/// The slip of the contacts that took one interaction, at the end of the mechanism.
struct FosSlip {
  std::string name;  // the joint's name, or "rock/bedrock"
  int joint = -1;    // index into scene.joints, -1: a material pair
  int material_a = -1, material_b = -1;
  int contacts = 0, slipping = 0;  // slipping: slip at least kMoveShare of the largest slip
  double total_slip = 0.0, max_slip = 0.0;  // m
};

struct FosMechanism {
  double factor = 0.0;
  std::string dir;            // the folder of its files
  bool same_bits = false;     // the rerun reached the search's state hash at its decision
  double decided_time = 0.0;  // s since the trial's start
  double time = 0.0;          // s, at the end of the run-on
  double max_reach = 0.0;     // m, the largest reach of a block over the run-on
  std::int64_t steps = 0;     // of the trial, equilibrium included
  int snapshots = 0;
  std::string stopped_by;  // "window", "size" (kRunOnFraction reached), "time_cap" or a signal
  int free_blocks = 0;
  std::vector<FosBlockMotion> blocks;  // the free blocks that move, by uid
  std::vector<FosSlip> slips;          // every interaction with a contact, most slip first
  std::string governing;               // slips[0].name; "" without slip
  std::map<std::string, int> modes;    // moving blocks per mode
  std::string summary;                 // one line: "plane sliding of 23 blocks on 'base'"
};

/// Runs the failed trial `failed` of the search again on `comm` (collective) with snapshots,
/// series.csv and blocks.csv in `dir`, on past its decision (see above), and measures its
/// mechanism. Every rank returns the whole result. `then`, if given, gets the simulation at the
/// end of the run-on (collective): `polydem fos --runout` runs the failure on from there.
FosMechanism runFosMechanism(const setup::Setup& scene, const FosTrial& failed,
                             const FosCriterion& criterion, const std::string& dir, MPI_Comm comm,
                             const std::function<void(sim::Simulation&)>& then = nullptr);

}  // namespace polydem::run
