#include "polydem/run/motion_checks.h"

#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <set>

#include "polydem/core/error.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/strings.h"
#include "polydem/run/free_motion.h"
#include "polydem/run/slope_turn.h"
#include "polydem/sim/simulation.h"

namespace polydem::run {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The parameters of one check, each read at most once; keys the kind does not know are errors.
class Keys {
 public:
  Keys(const setup::Setup& scene, const setup::CheckSpec& spec, std::set<std::string> known)
      : scene_(scene), spec_(spec) {
    for (const auto& [key, value] : spec.numbers) {
      if (!known.count(key)) fail(cat("unknown parameter '", key, "'"));
    }
    for (const auto& [key, value] : spec.strings) {
      if (!known.count(key)) fail(cat("unknown parameter '", key, "'"));
    }
  }
  [[noreturn]] void fail(const std::string& message) const {
    throw InputError(scene_.file, spec_.line,
                     cat("[[check]] '", spec_.name, "' (kind ", spec_.kind, "): ", message));
  }
  std::string text(const std::string& key, const std::string& fallback) const {
    const auto it = spec_.strings.find(key);
    if (it != spec_.strings.end()) return it->second;
    if (spec_.numbers.count(key)) fail("'" + key + "' must be a word, not a number");
    return fallback;
  }
  std::string choice(const std::string& key, const std::vector<std::string>& choices,
                     const std::string& fallback) const {
    const std::string v = text(key, fallback);
    for (const auto& c : choices) {
      if (v == c) return v;
    }
    fail(cat("'", key, "' must be one of ", join(choices, ", "), ", got '", v, "'"));
  }
  double number(const std::string& key, std::optional<double> fallback, double lo) const {
    const auto it = spec_.numbers.find(key);
    if (it == spec_.numbers.end()) {
      if (spec_.strings.count(key)) fail("'" + key + "' must be a number");
      if (!fallback) fail("needs the number '" + key + "'");
      return *fallback;
    }
    if (it->second.size() != 1) fail("'" + key + "' must be a single number");
    if (!(it->second[0] >= lo)) fail(cat("'", key, "' must be >= ", lo));
    return it->second[0];
  }
  std::optional<Vec3> direction(const std::string& key) const {
    const auto it = spec_.numbers.find(key);
    if (it == spec_.numbers.end()) return std::nullopt;
    if (it->second.size() != 3) fail("'" + key + "' must be a vector [x, y, z]");
    const Vec3 v(it->second[0], it->second[1], it->second[2]);
    if (!(v.norm() > 0)) fail("'" + key + "' must not be zero");
    return v.normalized();
  }
  /// The label prefix of the blocks, checked to select at least one free particle.
  std::string prefix(bool required) const {
    const std::string p = text("label_prefix", "");
    if (p.empty() && required) fail("needs 'label_prefix' (the blocks' labels: prefix_0, ...)");
    for (const auto& particle : scene_.particles) {
      if (!particle.fixed && particle.driver < 0 && matchesPrefix(particle.label, p)) return p;
    }
    fail(p.empty() ? std::string("the scene has no free particle")
                   : "no free particle is labelled '" + p + "' or '" + p + "_...'");
  }

 private:
  const setup::Setup& scene_;
  const setup::CheckSpec& spec_;
};

double pick(const FreeMotion& m, const std::string& quantity) {
  if (quantity == "mean_displacement") return m.mean_displacement;
  if (quantity == "max_displacement") return m.max_displacement;
  if (quantity == "mean_speed") return m.mean_speed;
  if (quantity == "max_speed") return m.max_speed;
  if (quantity == "max_angular_speed") return m.max_angular_speed;
  return m.front_advance;
}

class FreeMotionCheck : public Check {
 public:
  FreeMotionCheck(const setup::Setup& scene, const setup::CheckSpec& spec) : Check(spec) {
    const Keys k(scene, spec,
                 {"quantity", "label_prefix", "direction", "at", "after", "every", "limit"});
    quantity_ = k.choice("quantity",
                         {"mean_displacement", "max_displacement", "mean_speed", "max_speed",
                          "max_angular_speed", "front_advance"},
                         "");
    prefix_ = k.prefix(false);
    direction_ = k.direction("direction");
    if (quantity_ == "front_advance" && !direction_) k.fail("front_advance needs 'direction'");
    at_ = k.choice("at", {"end", "max", "first_below"}, "end");
    if (at_ == "first_below") limit_ = k.number("limit", std::nullopt, 0.0);
    after_ = k.number("after", 0.0, 0.0);
    every_ = static_cast<std::int64_t>(k.number("every", 1.0, 1.0));
  }
  void observe(const sim::Simulation& sim, const Tracker&) override {
    if (sim.stepCount() % every_ != 0) return;  // the same decision on every rank
    now_ = pick(meter(sim).measure(sim), quantity_);
    record(sim.time());
  }
  double value(sim::Simulation& sim) override {
    const FreeMotion m = meter(sim).measure(sim);
    now_ = pick(m, quantity_);
    record(sim.time());
    note = cat(m.particles, " free blocks at the end: mean displacement ", num(m.mean_displacement),
               " m, largest ", num(m.max_displacement), " m; mean speed ", num(m.mean_speed),
               " m/s; largest angular speed ", num(m.max_angular_speed), " rad/s");
    if (at_ == "end") return now_;
    if (at_ == "max") return sim.time() >= after_ ? largest_ : kNaN;
    if (std::isnan(first_below_))
      note += cat("; never below ", num(limit_), " after ", after_, " s");
    return first_below_;
  }
  std::vector<std::pair<std::string, double>> seriesColumns(const sim::Simulation&) const override {
    std::string name;
    for (char c : spec_.name) name += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
    return {{name, now_}};
  }
  std::vector<double> state() const override { return {now_, largest_, first_below_}; }
  void restore(const std::vector<double>& v) override {
    now_ = v.at(0);
    largest_ = v.at(1);
    first_below_ = v.at(2);
  }

 private:
  void record(double time) {
    if (!(time >= after_)) return;
    largest_ = std::max(largest_, now_);
    if (std::isnan(first_below_) && now_ < limit_) first_below_ = time;
  }
  const FreeMotionMeter& meter(const sim::Simulation& sim) {
    if (!meter_) meter_.emplace(sim, prefix_, direction_);
    return *meter_;
  }
  std::string quantity_, prefix_;
  std::optional<Vec3> direction_;
  std::string at_;
  double after_ = 0.0, limit_ = -INFINITY;
  std::int64_t every_ = 1;
  std::optional<FreeMotionMeter> meter_;
  double now_ = 0.0, largest_ = 0.0, first_below_ = kNaN;
};

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
    const double moved = kMovedFraction * reach_;
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
  double value_ = kNaN;
};

// The first time two particles that pressed on each other stop doing so (Zhao section 5.4: the
// front block of a pillar leaves the block behind it when the compression wave reaches it).
class PairSeparationCheck : public Check {
 public:
  PairSeparationCheck(const setup::Setup& scene, const setup::CheckSpec& spec) : Check(spec) {
    const Keys k(scene, spec, {"particle", "min_force"});
    // Pressing means a normal force above this: contacts that only touch at rest do not count.
    min_force_ = k.number("min_force", 0.0, 0.0);
    const std::string list = k.text("particle", "");
    const auto comma = list.find(',');
    if (comma == std::string::npos) k.fail("needs 'particle' = \"a,b\" (two labels)");
    Uid uids[2] = {0, 0};
    for (int i = 0; i < 2; ++i) {
      std::string label = i == 0 ? list.substr(0, comma) : list.substr(comma + 1);
      label.erase(0, label.find_first_not_of(' '));
      label.erase(label.find_last_not_of(' ') + 1);
      uids[i] = uidOfLabel(scene, label);
      if (uids[i] == 0) k.fail("no particle is labelled '" + label + "'");
    }
    if (uids[0] == uids[1]) k.fail("needs two different particles");
    key_ = particles::makeKey(uids[0], uids[1]);
  }
  void observe(const sim::Simulation& sim, const Tracker&) override {
    if (!std::isnan(time_)) return;
    double pressing = 0.0;
    for (const auto& r : sim.contacts().records()) {
      if (r.key == key_ && r.touching && r.normal_force > min_force_) pressing = 1.0;
    }
    pressing = mpi::allreduceMax(pressing, sim.comm());  // any rank that evaluated the pair
    if (pressing > 0.0) {
      pressed_ = true;
    } else if (pressed_) {
      time_ = sim.time();
      note = cat("particles ", key_.lo, " and ", key_.hi,
                 " pressed on each other until t = ", num(time_), " s");
    }
  }
  double value(sim::Simulation&) override {
    if (std::isnan(time_)) note = pressed_ ? "still pressing at the end" : "they never pressed";
    return time_;
  }
  std::vector<double> state() const override { return {pressed_ ? 1.0 : 0.0, time_}; }
  void restore(const std::vector<double>& v) override {
    pressed_ = v.at(0) != 0.0;
    time_ = v.at(1);
  }

 private:
  particles::PairKey key_;
  double min_force_ = 0.0;
  bool pressed_ = false;
  double time_ = kNaN;
};

}  // namespace

std::unique_ptr<Check> makeMotionCheck(const setup::Setup& scene, const setup::CheckSpec& spec,
                                       Tracker&) {
  if (spec.kind == "free_motion") return std::make_unique<FreeMotionCheck>(scene, spec);
  if (spec.kind == "tilt_failure") return std::make_unique<TiltFailureCheck>(scene, spec);
  if (spec.kind == "pair_separation") return std::make_unique<PairSeparationCheck>(scene, spec);
  return nullptr;
}

}  // namespace polydem::run
