// Check kind "free_motion": a FreeMotion statistic of the free blocks (or those of a label
// prefix): mean or largest displacement or speed, largest angular speed, or the front's advance
// along a direction; its value at the end, its largest after a given time, or the first time it
// falls below a limit after a given time. Its value now is a column of series.csv (the
// displacement history of a runout).
#include <cmath>
#include <limits>
#include <optional>

#include "polydem/core/mpi_env.h"
#include "polydem/core/strings.h"
#include "polydem/run/checks/keys.h"
#include "polydem/run/checks/kinds.h"
#include "polydem/run/checks/params.h"
#include "polydem/run/free_motion.h"
#include "polydem/sim/simulation.h"

namespace polydem::run::kinds {

namespace {

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
    if (at_ == "max") return sim.time() >= after_ ? largest_ : kNoValue;
    if (std::isnan(first_below_))
      note += cat("; never below ", num(limit_), " after ", after_, " s");
    return first_below_;
  }
  std::vector<std::pair<std::string, double>> seriesColumns(const sim::Simulation&) const override {
    return {{columnName(spec_.name), now_}};
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
  double now_ = 0.0, largest_ = 0.0, first_below_ = kNoValue;
};

}  // namespace

std::unique_ptr<Check> freeMotion(const setup::Setup& scene, const setup::CheckSpec& spec,
                                  Tracker&) {
  return std::make_unique<FreeMotionCheck>(scene, spec);
}

}  // namespace polydem::run::kinds
