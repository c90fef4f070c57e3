// Factor of safety by strength reduction, as geotechnical engineers define it (Dawson, Roth and
// Drescher 1999; 3DEC's "solve fos"): the strength of the chosen interactions is divided by F,
//   tan(phi_F) = tan(phi) / F,   c_F = c / F,
// and F is the largest factor for which the slope still comes to rest. A trial at F runs the
// scene with reduced strength until the watched free blocks are at rest (mean speed below the
// limit after the settling time: Keissar section 4.5 uses 1e-4 m/s), or until their mean
// displacement passes the limit (failed), or until max_time (still moving: failed). F is
// bisected between f_min and f_max until the bracket is `resolution` wide.
//
// Trials run side by side: the launched ranks are split into groups (MPI_Comm_split), each group
// runs one trial, and since a run is the same bits on any rank count, each trial's result is the
// same as if it ran alone. With G groups a round tries G factors that divide the bracket into
// G + 1 equal parts.
#pragma once

#include <mpi.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "polydem/setup/setup.h"

namespace polydem::sim {

/// The scene with the strength of its [fos] interactions (or of every material pair) divided by
/// `factor`: each such pair becomes an explicit [[interaction]] with friction angle
/// atan(tan(phi) / factor) and cohesion c / factor; stiffness and damping are unchanged. Every
/// [[joint]] is reduced likewise (its tensile strength too, as cohesion).
io::Scene reduceStrength(const io::Scene& scene, double factor);

/// The material pairs [fos] reduces (lower index first): its list, or every pair of materials.
std::vector<std::pair<int, int>> reducedPairs(const io::Scene& scene);

/// The criterion a trial is judged by, with every default resolved.
struct FosCriterion {
  double max_time = 0.0, settle_time = 0.0;  // s
  double speed_limit = 0.0;                  // m/s, of the mean speed
  double displacement_limit = 0.0;           // m, of the mean displacement
  std::int64_t check_every = 100;            // steps
  std::string label_prefix;                  // watched free blocks; empty: all
};

/// The [fos] settings of `scene` with their defaults (settle_time = max_time / 4, displacement
/// limit = 0.1 x the watched blocks' mean size, the cube root of their mean volume). Throws
/// InputError if max_time is given nowhere.
FosCriterion fosCriterion(const io::Scene& scene);

struct FosSample {
  double time = 0.0;               // s
  double mean_displacement = 0.0;  // m
  double mean_speed = 0.0;         // m/s
};

struct FosTrial {
  double factor = 0.0;
  std::string outcome;  // "stable", "failed" (displacement limit) or "moving" (at max_time)
  double mean_displacement = 0.0, max_displacement = 0.0, mean_speed = 0.0;  // at the end
  double time = 0.0;  // s, simulated, when the trial was decided
  std::int64_t steps = 0;
  std::uint64_t state_hash = 0;  // of the whole state at the end (comm::StateHash::combined)
  double wall_seconds = 0.0;
  int group = 0;                   // the group of ranks that ran it
  std::vector<FosSample> history;  // every check_every steps
  bool stable() const { return outcome == "stable"; }
};

/// One trial of `scene` at `factor` on `comm` (collective). The result is the same bits on any
/// rank count, wall_seconds and group aside.
FosTrial runFosTrial(const io::Scene& scene, double factor, const FosCriterion& criterion,
                     MPI_Comm comm);

struct FosResult {
  std::vector<FosTrial> trials;          // in the order they were run (round by round, F ascending)
  std::optional<double> stable, failed;  // the bracket: largest stable F below the smallest failed
  double resolution = 0.0;
  int groups = 1, ranks = 1;
  std::string note;  // below / above the range, or results that are not monotonic in F
  /// (stable + failed) / 2 when both are known.
  std::optional<double> factor() const;
};

/// Bisects on F with the trials spread over `groups` groups of the ranks of `comm` (collective;
/// every rank returns the whole result). `groups` must divide the rank count. `resolution`,
/// `f_min`, `f_max` default to the scene's [fos].
FosResult findFactorOfSafety(const io::Scene& scene, const FosCriterion& criterion, int groups,
                             MPI_Comm comm);

}  // namespace polydem::sim
