// A stable time step for the leapfrog from masses, inertia and contact stiffnesses.
//
// The leapfrog is stable for dt < 2 / omega_max, omega_max the highest eigenfrequency of the
// system. We follow the per-particle estimate of PFC3D ("Theory and Background", timestep
// determination) as written out in the Yade documentation (formulation, "Stability
// considerations"): a particle of mass m held by springs of total stiffness K, its neighbours
// moving the opposite way (apparent stiffness 2K), has omega^2 = 2K/m; the rotational analogue is
// 2 K R^2 / I, R the longest lever arm (the circumradius) and I the smallest principal moment.
// With viscous damping of ratio zeta the leapfrog's limit shrinks to (2/omega)(sqrt(1+zeta^2)-zeta)
// (the same factor as for the central difference method; docs/dynamics.md derives it). So, per
// free particle,
//   dt_crit = sqrt(2) (sqrt(1 + zeta^2) - zeta) min( sqrt(m / K), sqrt(I_min / (K R^2)) ),
//   K = coordination * k,  k = stiffest contact spring the particle may meet (max of kn and ks),
// and the suggestion is safety * min over particles of dt_crit. The coordination (default 6) is an
// estimate of the contacts a particle carries at once; the safety factor (default 0.8, the
// default of Yade's GlobalStiffnessTimeStepper) covers what the estimate leaves out (the coupling
// of translation and rotation by off-centre contacts, stiffening potential contacts).
#pragma once

#include <limits>
#include <span>
#include <string>

#include "polydem/core/types.h"
#include "polydem/particles/material.h"

namespace polydem::dynamics {

/// What the estimate needs to know of one free particle (fixed and driven ones are left out).
struct TimeStepParticle {
  Uid uid = 0;
  double mass = 0.0;                      // kg
  Vec3 principal_inertia = Vec3::Zero();  // kg m^2
  double circumradius = 0.0;              // m: longest lever arm of a contact force
  double stiffness = 0.0;                 // N/m: stiffest contact spring it may meet (see below)
  double damping_ratio = 0.0;             // largest viscous normal damping ratio it may meet
};

struct TimeStepRule {
  double coordination = 6.0;  // contacts carried at once by one particle
  double safety = 0.8;        // suggested dt = safety * critical dt
};

struct TimeStepSuggestion {
  double dt = std::numeric_limits<double>::infinity();        // safety * critical
  double critical = std::numeric_limits<double>::infinity();  // estimated stability limit
  Uid uid = 0;                                                // the particle that sets it
  bool rotational = false;  // set by its rotation (true) or its translation
};

/// The suggestion for a set of particles (infinite when no particle has a stiffness). The result is
/// a minimum, so ranks may each pass their own particles and reduce dt with MPI_MIN.
/// Throws polydem::Error for a particle with non-positive mass or inertia, negative stiffness or
/// damping, or a rule with coordination < 1 or safety outside (0, 1].
TimeStepSuggestion suggestTimeStep(std::span<const TimeStepParticle> particles,
                                   const TimeStepRule& rule = {});

/// Contact spring of a kPenalty pair: max(kn, ks).
double penaltyStiffness(const particles::ContactProperties& p);

/// Equivalent spring of a kPotential pair (Zhao eqs. 5, 13): with phi = h / r (r the inradius),
/// a face-to-face overlap of depth d over an area A has a potential of about A d (1/r_A + 1/r_B),
/// so f_n = penalty * potential grows like penalty * A * 2 / r * d for two equal particles.
/// `face_area`: the particle's largest face area (m^2); `inradius` in m. Returns the larger of
/// that and ks.
double potentialStiffness(const particles::ContactProperties& p, double face_area, double inradius);

/// Empty when dt <= suggestion.dt; otherwise a one-line warning naming dt, the suggestion, the
/// estimated limit and the particle (uid, rotation or translation) that sets it.
std::string timeStepWarning(double dt, const TimeStepSuggestion& suggestion);

}  // namespace polydem::dynamics
