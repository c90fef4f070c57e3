// Check kind "sliding_block" (Zhao eqs. 41-42): a block launched up an incline at u0, decelerated
// by gravity and friction, then either held by friction (tan(theta) <= mu) or sliding back down.
// s and u along `direction` (up the slope); the value is the largest error over the largest
// analytical value.
#include <cmath>

#include "polydem/run/checks/curve_check.h"
#include "polydem/run/checks/kinds.h"
#include "polydem/run/checks/params.h"

namespace polydem::run::kinds {

std::unique_ptr<Check> slidingBlock(const setup::Setup& scene, const setup::CheckSpec& spec,
                                    Tracker& t) {
  Params p(scene, spec);
  const Uid uid = p.particles(t).front();
  const double theta = degToRad(p.number("theta"));
  const double mu = p.number("mu");
  const double u0 = p.number("u0");
  const double g = p.number("g", scene.gravity.norm());
  const Vec3 dir = *p.vector("direction", true);
  const std::string quantity = p.text("quantity", "displacement");
  if (quantity != "displacement" && quantity != "velocity") {
    p.fail("'quantity' must be \"displacement\" or \"velocity\"");
  }
  const double up = g * (std::sin(theta) + mu * std::cos(theta));    // deceleration going up
  const double down = g * (std::sin(theta) - mu * std::cos(theta));  // acceleration coming down
  const double t1 = u0 / up, s0 = 0.5 * u0 * u0 / up;
  const bool slides_back = down > 0;
  CurveCheck::Curve curve;
  if (quantity == "displacement") {
    curve = [=](double time) {
      if (time <= t1) return u0 * time - 0.5 * up * time * time;
      const double tau = time - t1;
      return slides_back ? s0 - 0.5 * down * tau * tau : s0;
    };
  } else {
    curve = [=](double time) {
      if (time <= t1) return u0 - up * time;
      return slides_back ? -down * (time - t1) : 0.0;
    };
  }
  return std::make_unique<CurveCheck>(spec, uid, curve, quantity == "velocity", dir, false);
}

}  // namespace polydem::run::kinds
