#include "polydem/dynamics/time_step.h"

#include <algorithm>
#include <cmath>

#include "polydem/core/error.h"
#include "polydem/core/strings.h"

namespace polydem::dynamics {

TimeStepSuggestion suggestTimeStep(std::span<const TimeStepParticle> particles,
                                   const TimeStepRule& rule) {
  if (!(rule.coordination >= 1.0) || !(rule.safety > 0.0 && rule.safety <= 1.0)) {
    throw Error(cat("time step rule: coordination ", rule.coordination, " must be >= 1 and safety ",
                    rule.safety, " in (0, 1]"));
  }
  TimeStepSuggestion best;
  for (const TimeStepParticle& p : particles) {
    if (!(p.mass > 0.0 && p.principal_inertia.minCoeff() > 0.0 && p.circumradius >= 0.0 &&
          p.stiffness >= 0.0 && p.damping_ratio >= 0.0)) {
      throw Error(cat("time step estimate: particle ", p.uid, " has mass ", p.mass, ", inertia (",
                      p.principal_inertia.transpose(), "), circumradius ", p.circumradius,
                      ", stiffness ", p.stiffness, ", damping ratio ", p.damping_ratio));
    }
    if (p.stiffness == 0.0) continue;
    const double k_total = rule.coordination * p.stiffness;
    const double damping = std::sqrt(1.0 + p.damping_ratio * p.damping_ratio) - p.damping_ratio;
    const double scale = std::sqrt(2.0) * damping;
    const double translation = scale * std::sqrt(p.mass / k_total);
    const double r2 = p.circumradius * p.circumradius;
    const double rotation = r2 > 0.0
                                ? scale * std::sqrt(p.principal_inertia.minCoeff() / (k_total * r2))
                                : std::numeric_limits<double>::infinity();
    const double critical = std::min(translation, rotation);
    // Ties go to the lower uid, whatever the order of the particles.
    if (critical < best.critical || (critical == best.critical && p.uid < best.uid)) {
      best.critical = critical;
      best.uid = p.uid;
      best.rotational = rotation < translation;
    }
  }
  best.dt = rule.safety * best.critical;
  return best;
}

double penaltyStiffness(const particles::ContactProperties& p) {
  return std::max(p.kn, p.ks);
}

double potentialStiffness(const particles::ContactProperties& p, double face_area,
                          double inradius) {
  if (!(face_area > 0.0 && inradius > 0.0)) {
    throw Error(cat("potential stiffness: face area ", face_area, " and inradius ", inradius,
                    " must be > 0"));
  }
  return std::max(2.0 * p.penalty * face_area / inradius, p.ks);
}

std::string timeStepWarning(double dt, const TimeStepSuggestion& s) {
  if (dt <= s.dt) return {};
  return cat("time step ", dt, " s is larger than the suggested ", s.dt,
             " s (estimated stability limit ", s.critical, " s, set by the ",
             s.rotational ? "rotation" : "translation", " of particle ", s.uid,
             "); the run may become unstable");
}

}  // namespace polydem::dynamics
