// Every joint law's header: the structs named in joint_law_list.inc. Included by the registry
// (joint_law.cpp) and the sub-contact loop (sub_contact_law.cpp); a new law adds its header here.
#pragma once

#include "polydem/dynamics/joint_law_barton_bandis.h"
#include "polydem/dynamics/joint_law_coulomb.h"
#include "polydem/dynamics/joint_law_coulomb_residual.h"
