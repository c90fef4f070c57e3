// Check kind "kinetic_energy_ratio": a particle's kinetic energy after its first contact ends,
// over its energy just before that contact began (a restitution measure).
#include <limits>

#include "polydem/core/strings.h"
#include "polydem/run/checks/kinds.h"
#include "polydem/run/checks/params.h"

namespace polydem::run::kinds {

namespace {

class EnergyRatioCheck : public Check {
 public:
  EnergyRatioCheck(const setup::Setup& scene, const setup::CheckSpec& spec, Tracker& t)
      : Check(spec) {
    uid_ = Params(scene, spec).particles(t).front();
  }
  void observe(const sim::Simulation&, const Tracker& t) override {
    const auto& s = t.states()[t.slot(uid_)];
    if (phase_ == 0 && s.contacts == 0) before_ = s.kinetic_energy;
    if (phase_ == 0 && s.contacts > 0) phase_ = 1;
    if (phase_ == 1 && s.contacts == 0) {
      after_ = s.kinetic_energy;
      phase_ = 2;
    }
  }
  double value(sim::Simulation&) override {
    if (phase_ < 2) {
      note = phase_ == 0 ? "the particle never touched anything" : "the contact never ended";
      return std::numeric_limits<double>::quiet_NaN();
    }
    note = cat("kinetic energy ", before_, " J before contact, ", after_, " J after separation");
    return after_ / before_;
  }
  std::vector<double> state() const override { return {double(phase_), before_, after_}; }
  void restore(const std::vector<double>& v) override {
    phase_ = static_cast<int>(v.at(0));
    before_ = v.at(1);
    after_ = v.at(2);
  }

 private:
  Uid uid_ = 0;
  int phase_ = 0;  // 0 free fall, 1 in contact, 2 separated
  double before_ = 0.0, after_ = 0.0;
};

}  // namespace

std::unique_ptr<Check> kineticEnergyRatio(const setup::Setup& scene, const setup::CheckSpec& spec,
                                          Tracker& tracker) {
  return std::make_unique<EnergyRatioCheck>(scene, spec, tracker);
}

}  // namespace polydem::run::kinds
