// Check kind "rotation": the largest rotation angle of particles, optionally only the turn about
// an axis.
#include <algorithm>

#include "polydem/run/checks/kinds.h"
#include "polydem/run/checks/params.h"

namespace polydem::run::kinds {

namespace {

class RotationCheck : public Check {
 public:
  RotationCheck(const setup::Setup& scene, const setup::CheckSpec& spec, Tracker& t) : Check(spec) {
    Params p(scene, spec);
    uids_ = p.particles(t);
    axis_ = p.vector("axis");
  }
  void observe(const sim::Simulation&, const Tracker& t) override {
    for (Uid uid : uids_) {
      const int s = t.slot(uid);
      const Quat& q0 = t.initial()[s].orientation;
      const Quat& q = t.states()[s].orientation;
      value_ = std::max(value_, axis_ ? twistAngle(q0, q, *axis_) : rotationAngle(q0, q));
    }
  }
  double value(sim::Simulation&) override { return value_; }
  std::vector<double> state() const override { return {value_}; }
  void restore(const std::vector<double>& v) override { value_ = v.at(0); }

 private:
  std::vector<Uid> uids_;
  std::optional<Vec3> axis_;
  double value_ = 0.0;
};

}  // namespace

std::unique_ptr<Check> rotation(const setup::Setup& scene, const setup::CheckSpec& spec,
                                Tracker& tracker) {
  return std::make_unique<RotationCheck>(scene, spec, tracker);
}

}  // namespace polydem::run::kinds
