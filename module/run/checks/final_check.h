// A check whose whole value is read from the simulation at the end of the run (the kinds
// equilibrium_steps, mean_speed, max_speed, contact_count, max_contact_force).
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "polydem/run/checks.h"

namespace polydem::run {

class FinalCheck : public Check {
 public:
  /// `value(sim, note)` is the check's value; it may write a note for the reader.
  using Value = std::function<double(sim::Simulation& sim, std::string& note)>;
  FinalCheck(const setup::CheckSpec& spec, Value value) : Check(spec), value_(std::move(value)) {}
  void observe(const sim::Simulation&, const Tracker&) override {}
  double value(sim::Simulation& sim) override { return value_(sim, note); }

 private:
  Value value_;
};

}  // namespace polydem::run
