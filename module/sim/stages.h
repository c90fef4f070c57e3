// The stages of a run (Keissar section 3.3, after 3DEC): the leapfrog's start, an optional
// initial-equilibrium stage with heavy damping and high friction, then the main run with the
// scene's own values. Each stage is a loop (timeloop/time_loop.h) over the step of
// sim/step/step_list.cpp; the equilibrium stage runs in a loop of its own while the main stage's
// waits, parked. Stages acts on the step's state and owns what the stages add to it: the step
// hook, the parked loop and the equilibrium stage's record.
#pragma once

#include <cstdint>
#include <functional>

#include "polydem/core/timing_pool.h"
#include "polydem/sim/step/step_state.h"
#include "polydem/timeloop/time_loop.h"

namespace polydem::sim {

class Stages {
 public:
  explicit Stages(StepState& s) : s_(s), parked_loop_(s.comm) {}

  /// Registers the step with the current stage's loop: the operators, the step hook as a stop
  /// condition, the global monitors for the progress line.
  void registerSteps();
  /// Velocities of a scene are given at t = 0; the leapfrog keeps them at t - dt/2: the half
  /// kick of the forces at t = 0, which leaves no trace in the pair histories or bolts.
  void startLeapfrog();
  /// Runs (or continues) the equilibrium stage if the scene has one and it has not ended; returns
  /// its step count so far (see Simulation::runEquilibrium).
  std::int64_t runEquilibrium();
  /// Runs the main stage until the scene's end time or step count (or the step hook).
  timeloop::StopReason run();

  /// The stage a checkpoint recorded: its equilibrium steps and verdict, and whether it was
  /// written in the equilibrium stage (then that stage is entered, to be continued).
  void restore(std::int64_t equilibrium_steps, bool reached, bool in_equilibrium);

  /// Called after every complete step of either stage; true (alike on every rank) stops the
  /// current stage's loop with StopReason::kUserCondition.
  void setStepHook(std::function<bool()> hook) { step_hook_ = std::move(hook); }
  /// The main stage's loop while the equilibrium stage runs (a force operator added then joins
  /// both).
  timeloop::TimeLoop* parkedLoop() {
    return s_.stage == Stage::kEquilibrium ? &parked_loop_ : nullptr;
  }

  /// The equilibrium stage's steps as the last runEquilibrium returned them (or restored).
  std::int64_t equilibriumSteps() const { return equilibrium_steps_; }
  bool equilibriumReached() const { return equilibrium_reached_; }
  const TimingPool& equilibriumTiming() const { return equilibrium_timing_; }

 private:
  void enterEquilibrium();
  void leaveEquilibrium();

  StepState& s_;
  std::int64_t equilibrium_steps_ = 0;
  bool equilibrium_reached_ = false;
  bool equilibrium_done_ = false;  // the stage has ended (or never was), never to run again
  TimingPool equilibrium_timing_;
  timeloop::TimeLoop parked_loop_;  // the main stage's loop while the equilibrium stage runs
  std::function<bool()> step_hook_;
};

}  // namespace polydem::sim
