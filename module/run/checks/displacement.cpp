// Check kind "displacement": the largest (or final) displacement of particles, optionally only
// its component along a direction.
#include <algorithm>
#include <cmath>

#include "polydem/run/checks/kinds.h"
#include "polydem/run/checks/params.h"

namespace polydem::run::kinds {

namespace {

class DisplacementCheck : public Check {
 public:
  DisplacementCheck(const setup::Setup& scene, const setup::CheckSpec& spec, Tracker& t)
      : Check(spec) {
    Params p(scene, spec);
    uids_ = p.particles(t);
    direction_ = p.vector("direction");
    final_ = p.text("at", "max") == "end";
    if (p.text("at", "max") != "max" && !final_) p.fail("'at' must be \"max\" or \"end\"");
  }
  void observe(const sim::Simulation&, const Tracker& t) override {
    double now = 0.0;
    for (Uid uid : uids_) {
      const int s = t.slot(uid);
      const Vec3 d = t.states()[s].position - t.initial()[s].position;
      now = std::max(now, direction_ ? std::abs(d.dot(*direction_)) : d.norm());
    }
    value_ = final_ ? now : std::max(value_, now);
  }
  double value(sim::Simulation&) override { return value_; }
  std::vector<double> state() const override { return {value_}; }
  void restore(const std::vector<double>& v) override { value_ = v.at(0); }

 private:
  std::vector<Uid> uids_;
  std::optional<Vec3> direction_;
  bool final_ = false;
  double value_ = 0.0;
};

}  // namespace

std::unique_ptr<Check> displacement(const setup::Setup& scene, const setup::CheckSpec& spec,
                                    Tracker& tracker) {
  return std::make_unique<DisplacementCheck>(scene, spec, tracker);
}

}  // namespace polydem::run::kinds
