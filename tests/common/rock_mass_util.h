// Small builders shared by the rock-mass tests: a joint set from its orientation and spacing, and
// the volume of all blocks of a cut.
#pragma once

#include <string>

#include "polydem/geometry/rock_mass.h"

namespace polydem::geometry {

inline JointSet set(const std::string& name, double dip, double dip_direction, double spacing,
                    double offset = 0.0) {
  JointSet s;
  s.name = name;
  s.dip = dip;
  s.dip_direction = dip_direction;
  s.spacing = spacing;
  s.offset = offset;
  return s;
}

inline double totalVolume(const RockMass& m) {
  double v = 0.0;
  for (const RockBlock& b : m.blocks) v += b.volume;
  return v;
}

}  // namespace polydem::geometry
