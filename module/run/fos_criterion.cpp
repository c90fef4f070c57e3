// The criterion of `polydem fos` from a scene's [fos] (run/fos.h): defaults resolved, and refused
// where a trial could not answer it, with the file and line of the setting.
#include <algorithm>
#include <cmath>

#include "polydem/core/error.h"
#include "polydem/core/strings.h"
#include "polydem/run/fos.h"

namespace polydem::run {

namespace {

void checkInteractions(const setup::Setup& scene) {
  const setup::FosSpec& f = scene.fos;
  for (std::size_t i = 0; i < f.interactions.size(); ++i) {
    const auto [a, b] = f.interactions[i];
    if (pairUsable(scene, a, b)) continue;
    const int line = i < f.interaction_lines.size() ? f.interaction_lines[i] : f.line;
    throw InputError(
        scene.file, line,
        cat("[fos] interactions[", i, "] = [\"", scene.materials[a].name, "\", \"",
            scene.materials[b].name, "\"]: no contact of the scene can use this pair (",
            a == b ? "fewer than two particles of that material, or none of them free"
                   : "no particle of one of the materials, or none of them free",
            "): reducing it changes nothing, and every trial would be stable"));
  }
}

// A named joint must be one a contact of a free block can take, and something must be reduced.
void checkJoints(const setup::Setup& scene) {
  const setup::FosSpec& f = scene.fos;
  if (!f.joints_named) return;
  if (f.joints.empty() && f.interactions.empty()) {
    throw InputError(scene.file, f.line,
                     "[fos] joints = [] and no interactions: nothing would be reduced, and every "
                     "trial would be stable");
  }
  for (std::size_t i = 0; i < f.joints.size(); ++i) {
    if (jointUsable(scene, f.joints[i])) continue;
    const int line = i < f.joint_lines.size() ? f.joint_lines[i] : f.line;
    throw InputError(scene.file, line,
                     cat("[fos] joints[", i, "] = \"", scene.joints[f.joints[i]].name,
                         "\": no free block has a face on a plane that takes this joint (only "
                         "fixed rock, or no plane names it): reducing it changes nothing"));
  }
}

// The trial must be long enough to be judged, and the window must hold several evaluations.
void checkLengths(const setup::Setup& scene, const FosCriterion& c) {
  const setup::FosSpec& f = scene.fos;
  const double dt = scene.dt;
  const double trial_steps = c.max_time / dt;
  if (trial_steps < static_cast<double>(kFosMinTrialSteps)) {
    throw InputError(
        scene.file, f.max_time_line > 0 ? f.max_time_line : f.line,
        cat("[fos] max_time (or --max-time) = ", num(c.max_time), " s is ", num(trial_steps),
            " steps of dt = ", num(dt), " s; a trial needs at least ", kFosMinTrialSteps,
            " steps (", num(kFosMinTrialSteps * dt),
            " s): the contacts' elastic transients, a few periods of the stiffest contact, must "
            "die out before a trial can be judged at rest or still moving"));
  }
  if (!(c.window < c.max_time)) {
    throw InputError(scene.file, f.line, "[fos]: settle_time must be shorter than max_time");
  }
  const double window_steps = c.window / dt;
  if (static_cast<double>(c.check_every) * kFosMinWindowChecks > window_steps) {
    throw InputError(
        scene.file, f.check_every_line > 0 ? f.check_every_line : f.line,
        cat("[fos] check_every = ", c.check_every,
            " steps: the window (settle_time = ", num(c.window), " s, ", num(window_steps),
            " steps of a trial of ", num(trial_steps), ") must hold at least ", kFosMinWindowChecks,
            " evaluations to tell decaying speeds from growing ones; give check_every <= ",
            static_cast<std::int64_t>(window_steps / kFosMinWindowChecks),
            " (or a longer settle_time or max_time)"));
  }
}

}  // namespace

FosCriterion fosCriterion(const setup::Setup& scene) {
  const setup::FosSpec& f = scene.fos;
  FosCriterion c;
  if (!f.max_time) {
    throw InputError(scene.file, f.line,
                     "[fos]: give max_time (how long a trial runs before it is extended, if still "
                     "undecided, up to time_cap), in the scene or as --max-time");
  }
  c.max_time = *f.max_time;
  c.time_cap = std::max(f.time_cap.value_or(4.0 * c.max_time), c.max_time);
  c.window = f.settle_time.value_or(0.25 * c.max_time);
  c.force_ratio = f.force_ratio;
  c.speed_decay = f.speed_decay;
  c.damping_from_scene = f.local_damping.has_value();
  c.local_damping = f.local_damping.value_or(0.8);
  c.speed_limit = f.speed_limit;
  c.displacement_limit = f.displacement_limit;
  c.label_prefix = f.label_prefix;
  c.check_every = f.check_every;
  checkLengths(scene, c);
  checkInteractions(scene);
  checkJoints(scene);
  return c;
}

std::string FosCriterion::describe() const {
  std::string s = cat(
      "static solution with local damping ", num(local_damping),
      damping_from_scene ? " ([fos] local_damping)" : " (3DEC's static value; [fos] local_damping)",
      " from the settled unreduced slope; every ", check_every,
      " steps: failed when a block's reach (|d| + theta R) from the settled state passes ",
      num(moved_fraction), " of its size V^(1/3)");
  if (displacement_limit)
    s += cat(" or the mean displacement passes ", num(*displacement_limit), " m");
  s += cat(", or when over the last ", num(window),
           " s the mean speed has not decayed while the largest reach grew by more than ",
           num(growth_fraction), " of the block's size; after ", num(window),
           " s stable when the force ratio < ", num(force_ratio), " and the largest speed < ",
           num(speed_decay),
           " x its peak, or when over the last window the largest reach grew by less than ",
           num(rest_fraction), " of the block's size, no faster in its second half");
  if (speed_limit) s += cat(" and the mean speed < ", num(*speed_limit), " m/s");
  s += cat("; undecided at ", num(max_time), " s: extended up to ", num(time_cap),
           " s, then reported undecided");
  return s;
}

}  // namespace polydem::run
