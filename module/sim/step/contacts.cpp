// Operator "contacts": the contact phase (sim/contact_phase.h) over the broad phase's candidates,
// and the load model's measure of its work (sim/load_balance.h).
#include "polydem/sim/step/operators.h"

namespace polydem::sim {

ContactSetup contactSetup(const StepState& s) {
  ContactSetup setup;
  setup.shapes = &s.shapes;
  setup.kernel = s.kernel.get();
  setup.law = s.stage == Stage::kEquilibrium ? &s.law_equilibrium : &s.law_main;
  setup.materials = static_cast<int>(s.materials.size());
  setup.plane_joint = &s.plane_joint;
  setup.joint_law = s.stage == Stage::kEquilibrium ? &s.joint_law_equilibrium : &s.joint_law_main;
  setup.drivers = &s.scene.drivers;
  setup.model = s.contact_model;
  setup.overlap_centroid = s.overlap_centroid;
  setup.margin = s.margin;
  setup.dt = s.dt();
  setup.time = s.stage == Stage::kEquilibrium ? 0.0 : s.time();
  return setup;
}

void computeContacts(StepState& s) {
  // Early work of an older ghost epoch was made from a state that changed since (step_state.h).
  if (s.early_epoch != s.ghost_epoch) s.contact_phase.discardEarly();
  s.contact_stats =
      s.contact_phase.run(contactSetup(s), s.storage, s.candidates, s.history, s.forces);
  // The work of this phase, and where it was if the decomposition is weighed after this step
  // (the work entries hold storage indices, valid only until the particles move).
  const bool sample = s.balancer.samples(s.loop.step() + 1, s.scene.domain.rebalance_every);
  s.balancer.record(s.storage, s.contact_phase.work(), sample);
}

}  // namespace polydem::sim
