// The run-on of a failing slope until at rest, with its checkpoints (run/runout.h); the deposit's
// measures are in runout_deposit.cpp.
#include "polydem/run/runout.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "polydem/checkpoint/checkpoint.h"
#include "polydem/core/error.h"
#include "polydem/core/logging.h"
#include "polydem/core/strings.h"
#include "polydem/core/test_pause.h"
#include "polydem/run/free_motion.h"
#include "polydem/run/run_checkpoint.h"
#include "polydem/sim/simulation.h"

namespace polydem::run {

namespace {

// DIR/runout.h5 with the state and the run-on's counters (collective).
std::string writeRunoutCheckpoint(sim::Simulation& sim, const RunoutSettings& s,
                                  const RunoutProgress& progress) {
  if (s.dir.empty()) return "";
  const std::filesystem::path path = std::filesystem::path(s.dir) / "runout.h5";
  const sim::CheckpointData data = sim.checkpointForWriting(
      s.scene_text, s.scene_file, runoutStateJson(progress, s, sim.scene()));
  checkpoint::writeCheckpoint(checkpoint::checkpointTarget(path, sim.comm()), data, sim.comm());
  return path.string();
}

}  // namespace

double largestSpeedRatio(const sim::Simulation& sim) {
  const double g = std::max(sim.scene().gravity.norm(), 1e-300);
  const auto& storage = sim.particles();
  double local = 0.0;
  for (std::size_t i = 0; i < storage.localCount(); ++i) {
    const auto& p = storage[i];
    if (!p.isFree()) continue;
    const auto& shape = sim.shapes()[p.shape];
    const dynamics::MassProperties mp = sim.massProperties(i);
    const Vec3 w = particles::angularVelocityOf(p.orientation.toRotationMatrix(),
                                                mp.principal_inertia, p.angular_momentum);
    const double speed = p.velocity.norm() + w.norm() * shape.circumradius;
    local = std::max(local, speed / std::sqrt(g * std::cbrt(shape.volume)));
  }
  double global = 0.0;
  MPI_Allreduce(&local, &global, 1, MPI_DOUBLE, MPI_MAX, sim.comm());
  return global;
}

RunoutResult runRunout(sim::Simulation& sim, const RunoutSettings& s, RunoutProgress progress) {
  if (!(s.time_cap > 0.0) || s.check_every < 1) {
    throw Error("runout: the time cap must be > 0 and check_every >= 1");
  }
  RunoutResult r;
  const FreeMotionMeter meter(sim);
  std::int64_t since_checkpoint = 0;
  testPause("runout-start");  // test hook: a signal here stops the run-on after its next step
  for (;;) {
    if (sim.time() - progress.start_time >= s.time_cap) {
      r.stopped_by = "time_cap";
      break;
    }
    // Checks on the steps that are multiples of check_every, so that a run-on continued from a
    // checkpoint written between two checks (a stop signal) checks, and stops, on the same steps.
    const std::int64_t round = s.check_every - sim.stepCount() % s.check_every;
    int sig = 0;
    for (std::int64_t k = 0; k < round && sig == 0; ++k) {
      sim.step();
      sig = stopSignalOnAnyRank(sim.comm());  // finish this step, then stop
    }
    if (sig != 0) {
      r.stopped_by = signalName(sig);
      r.checkpoint = writeRunoutCheckpoint(sim, s, progress);
      break;
    }
    r.max_speed_ratio = largestSpeedRatio(sim);
    const FreeMotion m = meter.measure(sim);
    r.series.push_back(
        {sim.time() - progress.start_time, m.mean_displacement, m.mean_speed, r.max_speed_ratio});
    progress.rest_checks = r.max_speed_ratio < kRestSpeed ? progress.rest_checks + 1 : 0;
    if (progress.rest_checks >= kRestChecks) {
      r.stopped_by = "rest";
      r.at_rest = true;
      break;
    }
    since_checkpoint += round;
    if (s.checkpoint_every > 0 && since_checkpoint >= s.checkpoint_every) {
      writeRunoutCheckpoint(sim, s, progress);
      since_checkpoint = 0;
    }
  }
  if (r.max_speed_ratio == 0.0) r.max_speed_ratio = largestSpeedRatio(sim);
  r.time = sim.time() - progress.start_time;
  r.steps = sim.stepCount();
  r.state_hash = sim.stateHash().combined;
  r.deposit = measureDeposit(sim, s.cell);
  return r;
}

std::string runoutStateJson(const RunoutProgress& progress, const RunoutSettings& settings,
                            const setup::Setup& scene) {
  nlohmann::json j;
  j["kernel"] = scene.kernel;
  j["contact_model"] = scene.contact_model;
  j["runout"] = {{"start_time", progress.start_time},
                 {"rest_checks", progress.rest_checks},
                 {"time_cap", settings.time_cap},
                 {"check_every", settings.check_every},
                 {"cell", settings.cell},
                 {"checkpoint_every", settings.checkpoint_every}};
  return j.dump();
}

RunoutProgress runoutStateFrom(const std::string& json, const std::string& file,
                               RunoutSettings& settings) {
  try {
    const auto j = nlohmann::json::parse(json).at("runout");
    RunoutProgress p;
    p.start_time = j.at("start_time").get<double>();
    p.rest_checks = j.at("rest_checks").get<int>();
    settings.time_cap = j.at("time_cap").get<double>();
    settings.check_every = j.at("check_every").get<std::int64_t>();
    settings.cell = j.at("cell").get<double>();
    settings.checkpoint_every = j.at("checkpoint_every").get<std::int64_t>();
    return p;
  } catch (const std::exception& e) {
    throw CheckpointError(cat(file, ": not a runout checkpoint (/run/state: ", e.what(), ")"));
  }
}

}  // namespace polydem::run
