// One step on each rank, as a list of named operators (operators.h) that step_list.cpp composes
// in the order they run; the loop (timeloop/time_loop.h) times each under its name.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "polydem/sim/step/step_state.h"
#include "polydem/timeloop/time_loop.h"

namespace polydem::sim {

/// Registers the step with `loop`: every operator in order, the user force operators of
/// s.force_operators where the list has its "force operators" entry, the observers after the
/// step count.
void addStep(timeloop::TimeLoop& loop, StepState& s);
/// Adds the user force operator s.force_operators[k] (the last added) to a loop that holds the
/// step, after the ones added before it, under its own name.
void addUserOperator(timeloop::TimeLoop& loop, StepState& s, std::size_t k);
/// Whether `name` is that of an operator of the step (a user operator may not take it).
bool isStepOperator(const std::string& name);
/// The forces of the current state outside the loop (untimed): the operators of the list's
/// force part, "derived" to "force ratio", user force operators included. The leapfrog's start.
void computeForces(StepState& s);

}  // namespace polydem::sim
