#include "polydem/run/checks/curve_check.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "polydem/core/strings.h"
#include "polydem/run/checks/params.h"
#include "polydem/sim/simulation.h"

namespace polydem::run {

CurveCheck::CurveCheck(const setup::CheckSpec& spec, Uid uid, Curve analytic, bool velocity,
                       Vec3 direction, bool relative_to_final)
    : Check(spec),
      uid_(uid),
      analytic_(std::move(analytic)),
      velocity_(velocity),
      direction_(direction),
      relative_to_final_(relative_to_final) {}

void CurveCheck::observe(const sim::Simulation& sim, const Tracker& t) {
  const int s = t.slot(uid_);
  // Positions are at t, leapfrog velocities at t - dt/2: compare each at its own time.
  const double time = velocity_ ? sim.time() - 0.5 * sim.dt() : sim.time();
  numeric_ = velocity_ ? t.states()[s].velocity.dot(direction_)
                       : (t.states()[s].position - t.initial()[s].position).dot(direction_);
  exact_ = analytic_(time);
  error_ = std::max(error_, std::abs(numeric_ - exact_));
  scale_ = relative_to_final_ ? std::abs(exact_) : std::max(scale_, std::abs(exact_));
}

double CurveCheck::value(sim::Simulation&) {
  note = cat("max |numerical - analytical| = ", error_, ", relative to ",
             relative_to_final_ ? "the final" : "the largest", " analytical value ", scale_);
  return scale_ > 0 ? error_ / scale_ : std::numeric_limits<double>::quiet_NaN();
}

std::vector<std::pair<std::string, double>> CurveCheck::seriesColumns(
    const sim::Simulation&) const {
  const std::string base = columnName(spec_.name);
  return {{base, numeric_}, {base + "_analytic", exact_}};
}

void CurveCheck::restore(const std::vector<double>& v) {
  numeric_ = v.at(0);
  exact_ = v.at(1);
  error_ = v.at(2);
  scale_ = v.at(3);
}

}  // namespace polydem::run
