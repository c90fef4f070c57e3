// The declarations of the built-in check kinds: one function per kind, each in its own file of
// this folder named after the kind (displacement.cpp declares "displacement"), whose computation
// is the file of the same name under module/run/checks/. check_table.cpp lists them.
#pragma once

#include "polydem/scene/check_kinds.h"

namespace polydem::scene::kinds {

CheckKind displacement();
CheckKind rotation();
CheckKind lateralDrift();
CheckKind slidingBlock();
CheckKind wedgeSlide();
CheckKind kineticEnergyRatio();
CheckKind separationTime();
CheckKind equilibriumSteps();
CheckKind meanSpeed();
CheckKind maxSpeed();
CheckKind contactCount();
CheckKind maxContactForce();
CheckKind freeMotion();
CheckKind tiltFailure();
CheckKind pairSeparation();

}  // namespace polydem::scene::kinds
