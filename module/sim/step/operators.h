// The operators of one step, each a function of the step's state (step_state.h) in its own file
// under sim/step/, composed in the order they run by step_list.cpp (docs/architecture.md "One step
// on each rank"). Each runs under its own timer, named as in step_list.cpp.
#pragma once

#include <cstdint>
#include <vector>

#include "polydem/broadphase/broad_phase.h"
#include "polydem/sim/contact_phase.h"
#include "polydem/sim/step/step_state.h"

namespace polydem::sim {

// sort.cpp: the local particles into the broad phase's cell order, every domain.sort_every steps.
void sortParticles(StepState& s);

// derived.cpp: world vertices, rotations, driven bodies' angular velocities.
void updateDerived(StepState& s);

// broad_phase.cpp: candidate pairs over owned + ghost particles (a superset of the contact
// phase's own test), after checking that their records fit in memory.
void findCandidates(StepState& s);
/// The broad phase's pairs over the particles stored now.
void findPairs(StepState& s, std::vector<broadphase::CandidatePair>& out);
/// The broad phase's input from the storage; returns the largest radius.
double fillSphereSet(StepState& s);

// contacts.cpp: the contact phase (sim/contact_phase.h) and the load model's sample of its work.
void computeContacts(StepState& s);
/// The contact phase's setup for the current stage and time.
ContactSetup contactSetup(const StepState& s);

// body_forces.cpp: gravity, plus the pseudo-static earthquake load under [seismic].
void addBodyForces(StepState& s);

// water_forces.cpp: hydrostatic pressure on the joint faces under [water].
void addWaterPressure(StepState& s);

// bolt_forces.cpp: the [[bolt]]s' forces, from the gathered poses of the bolted blocks.
void addBoltForces(StepState& s);

// user_forces.cpp: one user force operator (sim/force_operator.h).
void applyForceOperator(StepState& s, const NamedForceOperator& op);
/// Calls `op` with `step`, marked as running (Simulation::requireBetweenSteps refuses meanwhile).
void callForceOperator(StepState& s, const std::string& name, const ForceOperator& op,
                       const ForceStep& step);

// force_ratio.cpp: this rank's sums of the force ratio (Keissar eq. 3.2).
void sumForceRatio(StepState& s);

// integrate.cpp: leapfrog for free particles, prescribed motion for driven ones, the ground's
// motion for fixed ones under [seismic].
void integrate(StepState& s);

// domain_check.cpp: every free particle finite and inside the domain.
void checkDomain(StepState& s);

// balance.cpp: a new decomposition weighed when rebalancing is due (sim/load_balancing.h).
void balanceWhenDue(StepState& s);

// exchange.cpp: migration with pair histories and ghost refresh, in two halves around the early
// contacts: the messages posted, then received.
void postExchange(StepState& s);
void finishExchange(StepState& s);
/// Fresh ghosts after a change of state between steps (a new ghost epoch: the early contacts
/// made before it are not used).
void refreshGhosts(StepState& s);

// early_contacts.cpp: the next contact phase's pairs of two local particles, while the exchange's
// messages travel.
void evaluateEarlyContacts(StepState& s);

// observers.cpp: checks, series, snapshots, checkpoints (module run), when due.
void observe(StepState& s);

}  // namespace polydem::sim
