// Check kind "lateral_drift": the largest drift of a particle across `lateral`, relative to its
// final travel along `direction`.
#include <algorithm>
#include <cmath>
#include <limits>

#include "polydem/core/strings.h"
#include "polydem/run/checks/kinds.h"
#include "polydem/run/checks/params.h"

namespace polydem::run::kinds {

namespace {

class LateralDriftCheck : public Check {
 public:
  LateralDriftCheck(const setup::Setup& scene, const setup::CheckSpec& spec, Tracker& t)
      : Check(spec) {
    Params p(scene, spec);
    uid_ = p.particles(t).front();
    direction_ = *p.vector("direction", true);
    lateral_ = *p.vector("lateral", true);
  }
  void observe(const sim::Simulation&, const Tracker& t) override {
    const int s = t.slot(uid_);
    const Vec3 d = t.states()[s].position - t.initial()[s].position;
    drift_ = std::max(drift_, std::abs(d.dot(lateral_)));
    travel_ = d.dot(direction_);
  }
  double value(sim::Simulation&) override {
    note = cat("lateral drift ", drift_, " m over a travel of ", travel_, " m");
    return travel_ > 0 ? drift_ / travel_ : std::numeric_limits<double>::quiet_NaN();
  }
  std::vector<double> state() const override { return {drift_, travel_}; }
  void restore(const std::vector<double>& v) override {
    drift_ = v.at(0);
    travel_ = v.at(1);
  }

 private:
  Uid uid_ = 0;
  Vec3 direction_, lateral_;
  double drift_ = 0.0, travel_ = 0.0;
};

}  // namespace

std::unique_ptr<Check> lateralDrift(const setup::Setup& scene, const setup::CheckSpec& spec,
                                    Tracker& tracker) {
  return std::make_unique<LateralDriftCheck>(scene, spec, tracker);
}

}  // namespace polydem::run::kinds
