#include "polydem/dynamics/integrator.h"

#include <cmath>
#include <utility>

#include "polydem/core/error.h"
#include "polydem/core/strings.h"

namespace polydem::dynamics {

Vec3 angularVelocity(const Quat& q, const Vec3& angular_momentum, const Vec3& principal_inertia) {
  const Vec3 body = q.conjugate() * angular_momentum;
  return q * body.cwiseQuotient(principal_inertia);
}

Vec3 angularMomentum(const Quat& q, const Vec3& angular_velocity, const Vec3& principal_inertia) {
  const Vec3 body = q.conjugate() * angular_velocity;
  return q * body.cwiseProduct(principal_inertia);
}

Vec3 localDamping(const Vec3& force, const Vec3& velocity, double alpha) {
  Vec3 out;
  for (int i = 0; i < 3; ++i) {
    const double sign = velocity[i] > 0.0 ? 1.0 : (velocity[i] < 0.0 ? -1.0 : 0.0);
    out[i] = force[i] - alpha * std::abs(force[i]) * sign;
  }
  return out;
}

namespace {

// sin and cos of x. The rotations of one DEM step are small, and for |x| <= 1/16 the Taylor
// polynomials below are exact to rounding (first omitted terms: x^11/11! and x^12/12!, below
// 1e-19 relative); they cost a few multiplications instead of two libm calls, and give the same
// bits on every machine whatever its libm.
inline void sinCos(double x, double& s, double& c) {
  if (std::abs(x) <= 0.0625) {
    const double x2 = x * x;
    s = x * (1.0 +
             x2 * (-1.0 / 6.0 + x2 * (1.0 / 120.0 + x2 * (-1.0 / 5040.0 + x2 * (1.0 / 362880.0)))));
    c = 1.0 +
        x2 * (-0.5 + x2 * (1.0 / 24.0 +
                           x2 * (-1.0 / 720.0 + x2 * (1.0 / 40320.0 + x2 * (-1.0 / 3628800.0)))));
  } else {
    s = std::sin(x);
    c = std::cos(x);
  }
}

// Exact flow of H_k = pi_k^2 / (2 I_k) over time h: the body turns about its axis k by
// phi = h pi_k / I_k (q <- q * exp(phi e_k / 2)), and the body-frame momentum turns the other way
// (pi <- R_k(-phi) pi) so that the world momentum q pi q^-1 is unchanged.
inline void rotateAboutAxis(int k, double h, const Vec3& inv_inertia, Vec3& pi, Quat& q) {
  double s, c;
  sinCos(0.5 * h * pi[k] * inv_inertia[k], s, c);
  const int i = (k + 1) % 3, j = (k + 2) % 3;
  // q * (c, s e_k), written out: the turn has one vector component, so 8 products instead of 16.
  Eigen::Vector4d& xyzw = q.coeffs();  // Eigen's storage order: x, y, z, w
  const double w = xyzw[3], vi = xyzw[i], vj = xyzw[j], vk = xyzw[k];
  xyzw[3] = c * w - s * vk;
  xyzw[k] = c * vk + s * w;
  xyzw[i] = c * vi + s * vj;
  xyzw[j] = c * vj - s * vi;
  // pi <- R_k(-phi) pi with cos(phi) and sin(phi) from the half angle.
  const double cos_phi = c * c - s * s, sin_phi = 2.0 * s * c;
  const double pi_i = pi[i], pi_j = pi[j];
  pi[i] = cos_phi * pi_i + sin_phi * pi_j;
  pi[j] = cos_phi * pi_j - sin_phi * pi_i;
}

}  // namespace

Quat freeRotation(const Quat& q, const Vec3& angular_momentum, const Vec3& principal_inertia,
                  double h) {
  const Vec3 inv_inertia = principal_inertia.cwiseInverse();
  Vec3 pi = q.conjugate() * angular_momentum;
  Quat out = q;
  // Strang splitting a(h/2) b(h/2) c(h) b(h/2) a(h/2) (Dullweber, Leimkuhler & McLachlan 1997)
  // with the axes taken by increasing principal moment (a: smallest, c: largest). Every order is
  // symplectic and second-order; this one gave the smallest energy error on the asymmetric tops we
  // measured (up to 10x smaller than the worst order; docs/dynamics.md). Ties keep index order.
  int a = 0, b = 1, c = 2;
  if (principal_inertia[b] < principal_inertia[a]) std::swap(a, b);
  if (principal_inertia[c] < principal_inertia[b]) std::swap(b, c);
  if (principal_inertia[b] < principal_inertia[a]) std::swap(a, b);
  rotateAboutAxis(a, 0.5 * h, inv_inertia, pi, out);
  rotateAboutAxis(b, 0.5 * h, inv_inertia, pi, out);
  rotateAboutAxis(c, h, inv_inertia, pi, out);
  rotateAboutAxis(b, 0.5 * h, inv_inertia, pi, out);
  rotateAboutAxis(a, 0.5 * h, inv_inertia, pi, out);
  out.normalize();
  return out;
}

void advanceFree(particles::Particle& p, const MassProperties& mass, const Vec3& force,
                 const Vec3& torque, double dt, double local_damping) {
  if (!p.isFree()) return;
  if (!std::isfinite(force.sum() + torque.sum())) {
    throw SimulationError(cat("particle ", p.uid, ": non-finite force (", force.transpose(),
                              ") or torque (", torque.transpose(), ")"));
  }
  Vec3 f = force, t = torque;
  if (local_damping > 0.0) {
    f = localDamping(force, p.velocity, local_damping);
    const Vec3 w = angularVelocity(p.orientation, p.angular_momentum, mass.principal_inertia);
    t = localDamping(torque, w, local_damping);
  }
  p.velocity += (dt / mass.mass) * f;
  p.position += dt * p.velocity;
  p.angular_momentum += dt * t;
  p.orientation = freeRotation(p.orientation, p.angular_momentum, mass.principal_inertia, dt);
}

void startLeapfrog(particles::Particle& p, const MassProperties& mass, const Vec3& force,
                   const Vec3& torque, double dt) {
  if (!p.isFree()) return;
  p.velocity -= (0.5 * dt / mass.mass) * force;
  p.angular_momentum -= (0.5 * dt) * torque;
}

}  // namespace polydem::dynamics
