// A scene's random inputs ([[random]] and [realizations], docs/scene-format.md) and the scenes of
// its realizations, for a probability-of-failure study (`polydem fos --realizations N`).
//
// Each [[random]] entry names a value of the scene file by its path
// (`joint.bedding.friction_angle`, `interaction.rock/base.friction_angle`, `water.level`,
// `seismic.kh`, `rock_mass.slope.joint_set.J1.spacing`) and draws it from a distribution:
// normal, lognormal, uniform, truncated (a normal truncated to [min, max]) or, for the
// orientation of a joint set or plane, fisher (its pole from Fisher's distribution about the
// file's one). Realization i is the scene file with these values replaced by draws from its own
// seed, splitMix64(seed of the study, i): the same on any rank, whichever group runs it. Every
// joint set's own seed (its spacing and orientation scatter) is derived from it too.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "polydem/setup/setup.h"

namespace polydem::scene {

/// One [[random]] entry.
struct RandomInput {
  std::string parameter;        // path of the value in the scene file
  std::string distribution;     // normal, lognormal, uniform, truncated, fisher
  double mean = 0.0, sd = 0.0;  // normal, lognormal (of the value itself), truncated
  double min = 0.0, max = 0.0;  // uniform, truncated
  double k = 0.0;               // fisher: concentration
  int line = 0;
};

/// A scene file with its random inputs.
struct Study {
  std::string file;        // the scene file
  std::string text;        // its text
  std::uint64_t seed = 1;  // [realizations] seed
  std::vector<RandomInput> inputs;
  /// The names of the drawn values, in realizations.csv's order: one per entry, two (dip,
  /// dip_direction) for a fisher entry.
  std::vector<std::string> columns() const;
};

/// One realization: its seed, the values drawn (in Study::columns() order) and its scene file's
/// text.
struct Realization {
  std::int64_t index = 0;
  std::uint64_t seed = 0;
  std::vector<double> values;
  std::string text;
};

/// Reads the [[random]] and [realizations] tables of the scene file at `path` and checks them:
/// InputError with the file and line for an unknown distribution, a parameter the file cannot
/// take, missing or bad bounds (sd <= 0, min >= max, a lognormal mean <= 0), and for a base
/// scene (every value as the file gives it) that does not read.
Study readStudy(const std::string& path);

/// Realization `index` of `study` (its draws and scene text). Deterministic: the same on every
/// machine and rank.
Realization drawRealization(const Study& study, std::int64_t index);

/// The scene of a realization, read from its text. A draw the scene cannot take (a normal
/// friction angle below 0) throws InputError at the [[random]] entry's line, naming the
/// realization and the value.
setup::Setup realizationScene(const Study& study, const Realization& r);

/// The standard normal quantile Phi^-1(p), p in (0, 1), to a few ulps (Acklam's rational
/// approximation and one Halley step on erfc).
double normalQuantile(double p);

/// The standard normal cumulative distribution Phi(x).
double normalCdf(double x);

}  // namespace polydem::scene
