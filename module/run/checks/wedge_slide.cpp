// Check kind "wedge_slide" (Zhao eq. 45): a frictionless wedge sliding down the intersection line
// of two planes, s = g t^2 sin(theta) / 2; the value is the largest error over the final
// analytical travel.
#include <cmath>

#include "polydem/run/checks/curve_check.h"
#include "polydem/run/checks/kinds.h"
#include "polydem/run/checks/params.h"

namespace polydem::run::kinds {

std::unique_ptr<Check> wedgeSlide(const setup::Setup& scene, const setup::CheckSpec& spec,
                                  Tracker& t) {
  Params p(scene, spec);
  const Uid uid = p.particles(t).front();
  const double theta = degToRad(p.number("theta"));
  const double g = p.number("g", scene.gravity.norm());
  const Vec3 dir = *p.vector("direction", true);  // down the intersection line
  auto curve = [=](double time) { return 0.5 * g * time * time * std::sin(theta); };
  return std::make_unique<CurveCheck>(spec, uid, curve, false, dir, true);
}

}  // namespace polydem::run::kinds
