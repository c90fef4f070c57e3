// Check kind "separation_time": the first time a particle that was in contact has no contact
// left.
#include <cmath>
#include <limits>

#include "polydem/run/checks/kinds.h"
#include "polydem/run/checks/params.h"
#include "polydem/sim/simulation.h"

namespace polydem::run::kinds {

namespace {

class SeparationCheck : public Check {
 public:
  SeparationCheck(const setup::Setup& scene, const setup::CheckSpec& spec, Tracker& t)
      : Check(spec) {
    uid_ = Params(scene, spec).particles(t).front();
  }
  void observe(const sim::Simulation& sim, const Tracker& t) override {
    const int contacts = t.states()[t.slot(uid_)].contacts;
    if (contacts > 0) touched_ = true;
    // A step's contacts are those of the positions at its start, time() - dt.
    if (touched_ && contacts == 0 && std::isnan(time_)) time_ = sim.time() - sim.dt();
  }
  double value(sim::Simulation&) override {
    if (std::isnan(time_)) note = touched_ ? "still in contact at the end" : "never in contact";
    return time_;
  }
  std::vector<double> state() const override { return {touched_ ? 1.0 : 0.0, time_}; }
  void restore(const std::vector<double>& v) override {
    touched_ = v.at(0) != 0.0;
    time_ = v.at(1);
  }

 private:
  Uid uid_ = 0;
  bool touched_ = false;
  double time_ = std::numeric_limits<double>::quiet_NaN();
};

}  // namespace

std::unique_ptr<Check> separationTime(const setup::Setup& scene, const setup::CheckSpec& spec,
                                      Tracker& tracker) {
  return std::make_unique<SeparationCheck>(scene, spec, tracker);
}

}  // namespace polydem::run::kinds
