// Check kind "tilt_failure": blocks on a tilting platform (Zhao section 5.3). The platform's tilt
// (deg) when a block first moves `threshold` against it, or (measure = "rotation") the slope's
// turn (deg) when a block first moves `reach`: the mass-weighted median turn against the platform
// of the blocks that have moved reach / 10 (slope_turn.h): near 0 when the slope slides, large
// when it topples.
#include <cmath>
#include <limits>
#include <map>
#include <optional>

#include "polydem/core/mpi_env.h"
#include "polydem/core/strings.h"
#include "polydem/run/checks/keys.h"
#include "polydem/run/checks/kinds.h"
#include "polydem/run/free_motion.h"
#include "polydem/run/slope_turn.h"
#include "polydem/sim/simulation.h"

namespace polydem::run::kinds {

namespace {

// Blocks on a tilting platform: positions and orientations in the platform's frame.
class TiltFailureCheck : public Check {
 public:
  TiltFailureCheck(const setup::Setup& scene, const setup::CheckSpec& spec) : Check(spec) {
    const Keys k(scene, spec, {"platform", "label_prefix", "measure", "threshold", "reach"});
    const std::string platform = k.text("platform", "");
    if (platform.empty()) k.fail("needs 'platform' (the label of the driven platform)");
    bool found = false;
    for (const auto& p : scene.particles) {
      if (p.label != platform) continue;
      platform_ = p;
      found = p.driver >= 0;
    }
    if (!found) k.fail("'" + platform + "' is not the label of a driven particle");
    prefix_ = k.prefix(true);
    rotation_ = k.choice("measure", {"angle", "rotation"}, "angle") == "rotation";
    // The displacement against the platform that decides: failure, or where the turn is read.
    reach_ =
        rotation_ ? k.number("reach", std::nullopt, 0.0) : k.number("threshold", std::nullopt, 0.0);
    for (const auto& p : scene.particles) {
      if (!p.fixed && p.driver < 0 && matchesPrefix(p.label, prefix_)) blocks_.push_back(p);
    }
  }
  void observe(const sim::Simulation& sim, const Tracker&) override {
    if (!std::isnan(value_)) return;  // decided (the same on every rank)
    if (start_.empty()) start(sim);
    const particles::Particle* platform = find(sim, platform_.uid);
    const std::vector<BlockMove> moves = blockMoves(sim, *platform);
    // The largest displacement of a block in the platform's frame, and that block's turn.
    double local[2] = {0.0, 0.0};
    for (const BlockMove& m : moves) {
      if (m.displacement <= local[0]) continue;
      local[0] = m.displacement;
      local[1] = m.turn;
    }
    const double largest = mpi::allreduceMax(local[0], sim.comm());
    if (largest < reach_) return;
    const double first_turn = mpi::allreduceMax(local[0] == largest ? local[1] : -1.0, sim.comm());
    const double tilt = radToDeg(rotationAngle(platform0_, platform->orientation));
    note = cat("a block moved ", num(largest), " m against the platform at t = ", num(sim.time()),
               " s, tilt ", num(tilt), " deg; that block turned ", num(first_turn), " deg");
    if (!rotation_) {
      value_ = tilt;
      return;
    }
    // The mode is the slope's: the median turn of every block that has moved (slope_turn.h).
    const double moved = kTurnMovedFraction * reach_;
    std::vector<BlockMove> counted;
    for (const BlockMove& m : moves) {
      if (m.displacement >= moved) counted.push_back(m);
    }
    counted = mpi::allgatherv(counted, sim.comm());
    value_ = slopeTurn(counted, moved);
    note += cat("; the ", counted.size(), " blocks that had moved ", num(moved), " m turned ",
                num(value_), " deg (mass-weighted median)");
  }
  double value(sim::Simulation&) override {
    if (std::isnan(value_)) note = cat("no block moved ", num(reach_), " m against the platform");
    return value_;
  }
  std::vector<double> state() const override { return {value_}; }
  void restore(const std::vector<double>& v) override { value_ = v.at(0); }

 private:
  static const particles::Particle* find(const sim::Simulation& sim, Uid uid) {
    const auto& storage = sim.particles();
    for (std::size_t i = 0; i < storage.size(); ++i) {
      if (storage[i].uid == uid) return &storage[i];
    }
    throw SimulationError(
        cat("tilt_failure: the platform (particle ", uid, ") is not on this rank"));
  }
  // Each local block's displacement and turn against the platform since the start.
  std::vector<BlockMove> blockMoves(const sim::Simulation& sim,
                                    const particles::Particle& platform) const {
    const Quat q_platform = platform.orientation;
    std::vector<BlockMove> moves;
    const auto& storage = sim.particles();
    for (std::size_t i = 0; i < storage.localCount(); ++i) {
      const auto& p = storage[i];
      const auto it = index_.find(p.uid);
      if (!p.isFree() || it == index_.end()) continue;
      const auto& [x0, q0] = start_[it->second];
      const Vec3 x = q_platform.conjugate() * (p.position - platform.position);
      const Quat q = q_platform.conjugate() * p.orientation;
      moves.push_back({(x - x0).norm(), radToDeg(rotationAngle(q0, q)), storage.mass(i)});
    }
    return moves;
  }
  // Where the blocks start in the platform's frame, from the scene.
  void start(const sim::Simulation& sim) {
    platform0_ = sim.initialOrientation(platform_);
    const Vec3 c0 = sim.initialCentroid(platform_);
    for (const setup::ParticleSpec& b : blocks_) {
      index_[b.uid] = start_.size();
      start_.emplace_back(platform0_.conjugate() * (sim.initialCentroid(b) - c0),
                          platform0_.conjugate() * sim.initialOrientation(b));
    }
  }
  setup::ParticleSpec platform_;
  std::vector<setup::ParticleSpec> blocks_;
  std::string prefix_;
  bool rotation_ = false;
  double reach_ = 0.0;
  Quat platform0_ = Quat::Identity();
  std::map<Uid, std::size_t> index_;
  std::vector<std::pair<Vec3, Quat>> start_;
  double value_ = kNoValue;
};

}  // namespace

std::unique_ptr<Check> tiltFailure(const setup::Setup& scene, const setup::CheckSpec& spec,
                                   Tracker&) {
  return std::make_unique<TiltFailureCheck>(scene, spec);
}

}  // namespace polydem::run::kinds
