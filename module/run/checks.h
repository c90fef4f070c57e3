// Checks: the expected results of a scene (its [[check]] tables), computed from the run itself.
//
// Each check kind observes the run after every step (through the Tracker, which gathers the
// labelled particles it needs onto every rank) and turns what it saw into one value at the end,
// compared with the scene's expected value. Each kind is one file of module/run/checks/ named
// after it (free_motion.cpp computes "free_motion"), registered in checks/check_table.cpp; its
// parameters are declared in the file of the same name under module/scene/check_kinds/, and
// docs/scene-format.md lists them.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "polydem/output/summary_json.h"
#include "polydem/run/tracker.h"
#include "polydem/setup/setup.h"

namespace polydem::sim {
class Simulation;
}  // namespace polydem::sim

namespace polydem::run {

class Check {
 public:
  virtual ~Check() = default;
  /// Called after every step on every rank, with the tracker freshly gathered.
  virtual void observe(const sim::Simulation& sim, const Tracker& tracker) = 0;
  /// The value at the end of the run (collective: may reduce over ranks).
  virtual double value(sim::Simulation& sim) = 0;
  /// Extra series columns (name, value now) for series.csv, e.g. numerical vs analytical curves.
  virtual std::vector<std::pair<std::string, double>> seriesColumns(const sim::Simulation&) const {
    return {};
  }
  /// What the check has accumulated so far, as numbers, and back: a checkpoint stores it so that
  /// a restarted run ends with the values of a run that never stopped.
  virtual std::vector<double> state() const { return {}; }
  virtual void restore(const std::vector<double>& /*state*/) {}
  /// Whether it reads the contact phase's full records (sim::ContactPhase::records), which a run
  /// keeps only while something reads them.
  virtual bool readsContacts() const { return false; }
  const setup::CheckSpec& spec() const { return spec_; }
  std::string note;  // anything a reader needs to judge the value

 protected:
  explicit Check(setup::CheckSpec spec) : spec_(std::move(spec)) {}
  setup::CheckSpec spec_;
};

/// Builds the checks of a scene and registers the particles they track. Throws InputError (with
/// the check's line) for an unknown kind, a missing parameter or an unknown particle label.
std::vector<std::unique_ptr<Check>> makeChecks(const setup::Setup& scene, Tracker& tracker);

/// Final results, with pass/fail by the spec's comparison (collective).
std::vector<output::CheckResult> evaluateChecks(std::vector<std::unique_ptr<Check>>& checks,
                                                sim::Simulation& sim);

/// Uid of the particle labelled `label`, or 0.
Uid uidOfLabel(const setup::Setup& scene, const std::string& label);

}  // namespace polydem::run
