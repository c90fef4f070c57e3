// One step on each rank, top to bottom: the operators in the order they run, each timed under its
// name. docs/architecture.md "One step on each rank" lists the same names in the same order
// (scripts/dev/check-layout compares the two).
#include "polydem/sim/step/step_list.h"

#include <iterator>

#include "polydem/sim/step/operators.h"

namespace polydem::sim {

namespace {

enum class Part {
  kOrder,    // storage order only: no result changes
  kForces,   // the forces of the particles' current state (also the leapfrog's start)
  kMove,     // the particles to the next step
  kObserve,  // after the loop counts the step (step and time advanced)
};

struct Operator {
  const char* name;  // also its timer's name
  Part part;
  void (*run)(StepState&);  // nullptr: the user force operators, each under its own name
};

// clang-format off
constexpr Operator kStep[] = {
    {"sort",            Part::kOrder,   sortParticles},
    {"derived",         Part::kForces,  updateDerived},
    {"broadphase",      Part::kForces,  findCandidates},
    {"contacts",        Part::kForces,  computeContacts},
    {"body forces",     Part::kForces,  addBodyForces},
    {"water",           Part::kForces,  addWaterPressure},
    {"bolts",           Part::kForces,  addBoltForces},
    {"force operators", Part::kForces,  nullptr},
    {"force ratio",     Part::kForces,  sumForceRatio},
    {"integrate",       Part::kMove,    integrate},
    {"domain check",    Part::kMove,    checkDomain},
    {"balance",         Part::kMove,    balanceWhenDue},
    {"exchange",        Part::kMove,    postExchange},
    {"early contacts",  Part::kMove,    evaluateEarlyContacts},
    {"exchange finish", Part::kMove,    finishExchange},
    {"observers",       Part::kObserve, observe},
};
// clang-format on

// The operator after the user force operators: they are inserted before it.
const char* afterUserOperators() {
  for (std::size_t i = 0; i + 1 < std::size(kStep); ++i) {
    if (!kStep[i].run) return kStep[i + 1].name;
  }
  return nullptr;
}

timeloop::TimeLoop::Function userOperator(StepState& s, std::size_t k) {
  return [&s, k] { applyForceOperator(s, s.force_operators[k]); };
}

}  // namespace

void addStep(timeloop::TimeLoop& loop, StepState& s) {
  for (const Operator& op : kStep) {
    if (!op.run) {
      for (std::size_t k = 0; k < s.force_operators.size(); ++k) {
        loop.add(s.force_operators[k].name, userOperator(s, k));
      }
    } else if (op.part == Part::kObserve) {
      loop.addObserver(op.name, [&s, run = op.run] { run(s); });
    } else {
      loop.add(op.name, [&s, run = op.run] { run(s); });
    }
  }
}

void addUserOperator(timeloop::TimeLoop& loop, StepState& s, std::size_t k) {
  loop.insertBefore(afterUserOperators(), s.force_operators[k].name, userOperator(s, k));
}

bool isStepOperator(const std::string& name) {
  for (const Operator& op : kStep) {
    if (name == op.name) return true;
  }
  return false;
}

void computeForces(StepState& s) {
  for (const Operator& op : kStep) {
    if (op.part != Part::kForces) continue;
    if (op.run) {
      op.run(s);
    } else {
      for (const auto& user : s.force_operators) applyForceOperator(s, user);
    }
  }
}

}  // namespace polydem::sim
