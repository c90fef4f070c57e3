// Check kind "pair_separation": the first time two particles that pressed on each other stop
// (Zhao section 5.4).
#include <cmath>
#include <limits>
#include <optional>

#include "polydem/core/mpi_env.h"
#include "polydem/core/strings.h"
#include "polydem/run/checks/keys.h"
#include "polydem/run/checks/kinds.h"
#include "polydem/sim/simulation.h"

namespace polydem::run::kinds {

namespace {

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
  bool readsContacts() const override { return true; }
  std::vector<double> state() const override { return {pressed_ ? 1.0 : 0.0, time_}; }
  void restore(const std::vector<double>& v) override {
    pressed_ = v.at(0) != 0.0;
    time_ = v.at(1);
  }

 private:
  particles::PairKey key_;
  double min_force_ = 0.0;
  bool pressed_ = false;
  double time_ = kNoValue;
};

}  // namespace

std::unique_ptr<Check> pairSeparation(const setup::Setup& scene, const setup::CheckSpec& spec,
                                      Tracker&) {
  return std::make_unique<PairSeparationCheck>(scene, spec);
}

}  // namespace polydem::run::kinds
