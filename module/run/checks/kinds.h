// The built-in check kinds: one factory per kind, each in its own file of this folder named after
// the kind (displacement.cpp builds "displacement"), whose parameters are declared in the file of
// the same name under module/scene/check_kinds/. check_table.cpp registers them by name.
#pragma once

#include <limits>
#include <memory>

#include "polydem/run/checks.h"
#include "polydem/run/tracker.h"
#include "polydem/setup/setup.h"

namespace polydem::run::kinds {

/// A check's value not (yet) known: a check that has not decided.
inline constexpr double kNoValue = std::numeric_limits<double>::quiet_NaN();

std::unique_ptr<Check> displacement(const setup::Setup& scene, const setup::CheckSpec& spec,
                                    Tracker& tracker);
std::unique_ptr<Check> rotation(const setup::Setup& scene, const setup::CheckSpec& spec,
                                Tracker& tracker);
std::unique_ptr<Check> lateralDrift(const setup::Setup& scene, const setup::CheckSpec& spec,
                                    Tracker& tracker);
std::unique_ptr<Check> slidingBlock(const setup::Setup& scene, const setup::CheckSpec& spec,
                                    Tracker& tracker);
std::unique_ptr<Check> wedgeSlide(const setup::Setup& scene, const setup::CheckSpec& spec,
                                  Tracker& tracker);
std::unique_ptr<Check> kineticEnergyRatio(const setup::Setup& scene, const setup::CheckSpec& spec,
                                          Tracker& tracker);
std::unique_ptr<Check> separationTime(const setup::Setup& scene, const setup::CheckSpec& spec,
                                      Tracker& tracker);
std::unique_ptr<Check> equilibriumSteps(const setup::Setup& scene, const setup::CheckSpec& spec,
                                        Tracker& tracker);
std::unique_ptr<Check> meanSpeed(const setup::Setup& scene, const setup::CheckSpec& spec,
                                 Tracker& tracker);
std::unique_ptr<Check> maxSpeed(const setup::Setup& scene, const setup::CheckSpec& spec,
                                Tracker& tracker);
std::unique_ptr<Check> contactCount(const setup::Setup& scene, const setup::CheckSpec& spec,
                                    Tracker& tracker);
std::unique_ptr<Check> maxContactForce(const setup::Setup& scene, const setup::CheckSpec& spec,
                                       Tracker& tracker);
std::unique_ptr<Check> freeMotion(const setup::Setup& scene, const setup::CheckSpec& spec,
                                  Tracker& tracker);
std::unique_ptr<Check> tiltFailure(const setup::Setup& scene, const setup::CheckSpec& spec,
                                   Tracker& tracker);
std::unique_ptr<Check> pairSeparation(const setup::Setup& scene, const setup::CheckSpec& spec,
                                      Tracker& tracker);

}  // namespace polydem::run::kinds
