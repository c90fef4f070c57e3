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
  /// `reads_contacts`: `value` reads the contact records (Check::readsContacts).
  FinalCheck(const setup::CheckSpec& spec, Value value, bool reads_contacts = false)
      : Check(spec), value_(std::move(value)), reads_contacts_(reads_contacts) {}
  void observe(const sim::Simulation&, const Tracker&) override {}
  double value(sim::Simulation& sim) override { return value_(sim, note); }
  bool readsContacts() const override { return reads_contacts_; }

 private:
  Value value_;
  bool reads_contacts_ = false;
};

}  // namespace polydem::run
