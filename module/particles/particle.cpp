#include "polydem/particles/particle.h"

namespace polydem::particles {

void pack(SendBuffer& out, const Particle& p) {
  out << p.uid << p.shape << p.material << p.flags << p.driver << p.position << p.orientation
      << p.velocity << p.angular_momentum;
}

void unpack(RecvBuffer& in, Particle& p) {
  in >> p.uid >> p.shape >> p.material >> p.flags >> p.driver >> p.position >> p.orientation >>
      p.velocity >> p.angular_momentum;
}

}  // namespace polydem::particles
