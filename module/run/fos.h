// Factor of safety by strength reduction, as geotechnical engineers define it (Dawson, Roth and
// Drescher 1999; 3DEC's "solve fos"): the strength of the chosen interactions is divided by F,
//   tan(phi_F) = tan(phi) / F,   c_F = c / F,
// and F is the largest factor for which the slope still stands where it is.
//
// Every trial starts from one settled state of the unreduced slope (settleForFos): the scene's
// initial-equilibrium stage (Keissar section 3.3: local damping 0.8 and friction 89 deg until
// the unbalanced-force ratio R, Keissar eq. 3.2, is below force_ratio), or its own
// [equilibrium]. The gravity load is then carried elastically, so that a trial measures only the
// motion the reduction causes. A slope that leaves its place while it settles (a block moves
// moved_fraction of its size: a column that topples at any friction) does not stand at any
// strength: its trials start from the scene as placed. A search settles once per group of ranks
// (the same bits in every group, as a run is the same bits on any rank count) and keeps the state
// in memory.
//
// Each trial at F is a static solution, as 3DEC runs one: local damping 0.8 on every block
// (unless [fos] sets its own), whatever damping the scene's dynamic run uses, so that the answer
// does not depend on it. A trial is judged every check_every steps (run/fos_trial.cpp) on the
// watched blocks, each block's motion from the settled state measured by its reach |d| + theta R
// (centroid displacement d, rotation angle theta, circumradius R) over its size V^(1/3):
//   failed  some block's reach is above moved_fraction (1 %) of its size: the slope does not
//           stand where it was, whether it is still moving or has jammed further on (a toppling
//           set that rotates a few centimetres and locks has failed); or, after a window
//           (settle_time), their mean speed has not decayed over the window and the largest
//           relative reach grew in both halves of it, by more than growth_fraction (2e-5) of
//           the block's size over the window: the displacement keeps growing at a rate that
//           matters, not a creep of round-off and elastic noise;
//   stable  after a window, every block within moved_fraction of its size: R is below
//           force_ratio and the largest speed has decayed below speed_decay x its peak in the
//           trial; or the blocks have stopped moving: over the window the largest relative reach
//           grew by less than rest_fraction (1e-5), and no faster in the window's second half
//           than in its first (motion from rest under a net force grows ever faster; what is
//           left is round-off and elastic jitter, which can hold R above force_ratio);
// neither by max_time: the trial runs on up to time_cap, and is reported undecided if it is
// still neither then. Every test is a ratio, free of the scene's length scale and damping. F is
// k-sected between f_min and f_max, only ever on decided trials, until the bracket is
// `resolution` wide. A trial ends as soon as it is decided.
//
// Trials run side by side: the launched ranks are split into G groups (MPI_Comm_split), each
// group runs one trial, and since a run is the same bits on any rank count, each trial's result
// is the same as if it ran alone. A round tries G factors that divide the bracket into G + 1
// equal parts (k-section; bisection for G = 1). A stop signal (SIGTERM, SIGUSR1, SIGINT) ends the
// running trials after their current step; the finished trials are kept, and a search continued
// from them (`prior`) tries the same factors as one that never stopped.
#pragma once

#include <mpi.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "polydem/setup/setup.h"
#include "polydem/sim/saved_state.h"

namespace polydem::sim {
class Simulation;
}  // namespace polydem::sim

namespace polydem::run {

/// The scene with the strength of what [fos] reduces (reducedPairs, reducedJoints) divided by
/// `factor`: each such pair becomes an explicit [[interaction]] with friction angle
/// atan(tan(phi) / factor) and cohesion c / factor; stiffness and damping are unchanged. Each
/// such [[joint]] is reduced likewise (its tensile strength too, as cohesion).
setup::Setup reduceStrength(const setup::Setup& scene, double factor);

/// What [fos] reduces (run/fos_selection.cpp). Naming `interactions` or `joints` reduces only
/// what is named; naming neither reduces every material pair and every [[joint]] that a contact
/// of a free block can use (pairUsable, jointUsable): never one only fixed bodies share.
/// The material pairs reduced (lower index first).
std::vector<std::pair<int, int>> reducedPairs(const setup::Setup& scene);
/// The [[joint]]s reduced (indices into scene.joints, in [fos] or file order).
std::vector<int> reducedJoints(const setup::Setup& scene);
/// Whether some contact can be between materials a and b: two particles of these materials, at
/// least one of them free (fixed and driven bodies never meet each other's forces).
bool pairUsable(const setup::Setup& scene, int a, int b);
/// Whether some free block has a face on a plane that takes [[joint]] `joint`.
bool jointUsable(const setup::Setup& scene, int joint);

/// The fewest steps a trial may have (max_time / dt): the contacts' elastic transients, a few
/// periods of the stiffest contact at the usual 10 to 50 steps a period, must have died out
/// before a trial can be judged at rest or still accelerating.
constexpr std::int64_t kFosMinTrialSteps = 500;
/// The fewest evaluations a window (settle_time) must hold, so that "not decaying over the
/// window" compares more than two samples' noise.
constexpr std::int64_t kFosMinWindowChecks = 4;

/// The criterion a trial is judged by, with every default resolved.
struct FosCriterion {
  double max_time = 0.0;            // s: a trial still undecided then is extended ...
  double time_cap = 0.0;            // s: ... up to this; still undecided: reported as such
  double window = 0.0;              // s (settle_time): stable only after it; failure judged over it
  double force_ratio = 1e-5;        // stable: R (Keissar eq. 3.2) below it
  double speed_decay = 1e-3;        // stable: largest speed below it x its peak
  double moved_fraction = 1e-2;     // failed: a block's reach above it x its size
  double growth_fraction = 2e-5;    // failed: the largest relative reach grew by it in a window
  double rest_fraction = 1e-5;      // stable: ... grew by less in a window, not accelerating
  double local_damping = 0.8;       // of every block during the trials
  bool damping_from_scene = false;  // [fos] local_damping set it
  std::optional<double> speed_limit;         // m/s: stable also needs the mean speed below it
  std::optional<double> displacement_limit;  // m: failed also beyond it
  std::int64_t check_every = 100;            // steps
  std::string label_prefix;                  // watched free blocks; empty: all
  /// One sentence for the console and fos.json.
  std::string describe() const;
};

/// The [fos] settings of `scene` with their defaults, checked against what a trial can answer:
/// throws InputError (file and line) without max_time, for a max_time below kFosMinTrialSteps
/// steps, a check_every that leaves the window fewer than kFosMinWindowChecks evaluations, or
/// an interaction that no contact of the scene can use (no free particle of one of its
/// materials beside a particle of the other).
FosCriterion fosCriterion(const setup::Setup& scene);

struct FosSample {
  double time = 0.0;               // s since the trial's start
  double mean_displacement = 0.0;  // m
  double mean_speed = 0.0;         // m/s
  double max_speed = 0.0;          // m/s
  double force_ratio = 0.0;        // R, Keissar eq. 3.2
  double max_move = 0.0;           // the largest reach / size of a watched block
};

struct FosTrial {
  double factor = 0.0;
  std::string outcome;  // "stable", "failed", "undecided" (at time_cap) or "interrupted"
  double mean_displacement = 0.0, max_displacement = 0.0, mean_speed = 0.0;  // at the end
  double max_speed = 0.0, force_ratio = 0.0;                                 // at the end
  double max_move = 0.0;  // at the end: the largest reach / size of a watched block
  double time = 0.0;      // s, simulated, when the trial was decided
  std::int64_t steps = 0;
  bool extended = false;         // ran past max_time
  std::uint64_t state_hash = 0;  // of the whole state at the end (comm::StateHash::combined)
  double wall_seconds = 0.0;
  int group = 0;                   // the group of ranks that ran it
  int round = 0;                   // the round of the search it belongs to
  std::vector<FosSample> history;  // every check_every steps
  bool stable() const { return outcome == "stable"; }
  bool failed() const { return outcome == "failed"; }
  bool decided() const { return stable() || failed(); }
};

/// Watches a trial as it runs (the mechanism of a failed trial, run/fos_mechanism.h): after the
/// initial equilibrium, after every evaluation of the criterion, and once the trial is decided,
/// with the simulation in the state the trial's result (and state hash) describes. Not called
/// for an interrupted trial. Every call is collective over the trial's ranks.
class FosTrialObserver {
 public:
  virtual ~FosTrialObserver() = default;
  virtual void started(sim::Simulation& sim) = 0;
  virtual void checked(sim::Simulation& sim) = 0;
  virtual void decided(sim::Simulation& sim, const FosTrial& trial) = 0;
};

/// The settled state of the unreduced slope every trial starts from (settleForFos).
struct FosStart {
  sim::CheckpointData state;  // this rank's part, as Simulation::checkpoint() takes it
  std::int64_t steps = 0;
  bool reached = false;      // R fell below the stage's force ratio (else: its step cap)
  bool interrupted = false;  // a stop signal ended it: no trial can start from it
  bool moved = false;  // a block left the scene's place by moved_fraction of its size while it
                       // settled: the slope does not stand, trials start from the scene as placed
  double wall_seconds = 0.0;
};

/// Settles `scene` at its own strengths by its initial-equilibrium stage ([equilibrium] when the
/// scene enables one; otherwise the stage's defaults, local damping 0.8 and friction 89 deg,
/// until R < criterion.force_ratio, at most time_cap / dt steps), judged every check_every
/// steps as a trial is: it ends when a trial would be stable (or R falls below the stage's
/// threshold), velocities zeroed; `moved` when a trial would have failed. Collective over
/// `comm`; the same bits on any rank count.
FosStart settleForFos(const setup::Setup& scene, const FosCriterion& criterion, MPI_Comm comm);

/// One trial of `scene` at `factor` on `comm` (collective), from `start` (settleForFos of the
/// same scene on a communicator of the same size as `comm`). The result is the same bits on any
/// rank count, wall_seconds and group aside, with or without an observer. A stop signal
/// received by a rank of `comm` ends it after the current step with outcome "interrupted".
FosTrial runFosTrial(const setup::Setup& scene, const FosStart& start, double factor,
                     const FosCriterion& criterion, MPI_Comm comm,
                     FosTrialObserver* observer = nullptr);
/// The same, settling the scene first (the same bits as a trial of a search).
FosTrial runFosTrial(const setup::Setup& scene, double factor, const FosCriterion& criterion,
                     MPI_Comm comm, FosTrialObserver* observer = nullptr);

struct FosResult {
  std::vector<FosTrial> trials;  // decided and undecided, in the order of the search
  int rounds_complete = 0;       // trials of later rounds are those of a round a signal cut short
  std::optional<double> stable, failed;  // the bracket: largest stable F below the smallest failed
  bool resolved = false;    // the bracket is `resolution` wide (or as narrow as can be)
  bool complete = true;     // false: stopped by a signal, to be continued
  std::string stop_signal;  // "SIGTERM", ... when stopped
  double resolution = 0.0;
  int groups = 1, ranks = 1;
  std::string note;  // below / above the range, undecided trials, results not monotonic in F
  std::int64_t settle_steps = 0;  // the settled state every trial started from (settleForFos)
  bool settle_reached = false;
  bool settle_used = true;  // false: the slope left its place while settling (FosStart::moved)
  double settle_wall_seconds = 0.0;
  /// (stable + failed) / 2 when both are known and the bracket is resolved.
  std::optional<double> factor() const;
};

/// k-sects F with the trials spread over `groups` groups of the ranks of `comm` (collective;
/// every rank returns the whole result). `groups` must divide the rank count. `resolution`,
/// `f_min`, `f_max` come from the scene's [fos]. `prior`: the result of a search of the same
/// scene and settings that a signal stopped; its trials are taken as run, not run again.
FosResult findFactorOfSafety(const setup::Setup& scene, const FosCriterion& criterion, int groups,
                             MPI_Comm comm, const FosResult* prior = nullptr);

}  // namespace polydem::run
