// Built with -fno-math-errno and -fno-trapping-math (CMakeLists.txt): a square root that may set
// errno is a call the vectorizer cannot pack, and a select between two computed values is not
// made branch-free while an operation might trap. The roots here are of sums of squares, and no
// trap is enabled: no result changes. Every expression below is the one the single-sub-contact law
// computed (Eigen's Vector3d operations written out: a dot product is (x0 y0 + x1 y1) + x2 y2, a
// scalar times a vector multiplies each coordinate, a vector over a scalar divides each), and every
// choice is a select between values computed in every lane, so that the loops have no branch.
#include "polydem/dynamics/sub_contact_lanes.h"

#include <algorithm>
#include <cmath>

// The lane arrays of one pair never overlap one another: tell the vectorizer, which cannot see
// that they are disjoint parts of one buffer.
#if defined(__GNUC__) && !defined(__clang__)
#define POLYDEM_LANES _Pragma("GCC ivdep")
#elif defined(__clang__)
#define POLYDEM_LANES _Pragma("clang loop vectorize(assume_safety)")
#else
#define POLYDEM_LANES
#endif

namespace polydem::dynamics {

namespace {

constexpr std::size_t kVecArrays = 8, kScalarArrays = 6;  // as SubLanes holds

VecLanes vecLanes(double*& next, std::size_t stride) {
  VecLanes v{next, next + stride, next + 2 * stride};
  next += 3 * stride;
  return v;
}

double* scalarLanes(double*& next, std::size_t stride) {
  double* s = next;
  next += stride;
  return s;
}

}  // namespace

SubLanes SubContactLanes::open(std::size_t lanes) {
  // Even, so that each array starts on 16 bytes (the vector's storage does) and a pair of lanes
  // never straddles two arrays.
  const std::size_t stride = (lanes + 1) & ~std::size_t{1};
  const std::size_t size = (3 * kVecArrays + kScalarArrays) * stride;
  if (storage_.size() < size) storage_.resize(size);
  double* next = storage_.data();
  SubLanes l;
  l.point = vecLanes(next, stride);
  l.normal = vecLanes(next, stride);
  l.shear = vecLanes(next, stride);
  l.old_normal = vecLanes(next, stride);
  l.force = vecLanes(next, stride);
  l.torque_a = vecLanes(next, stride);
  l.torque_b = vecLanes(next, stride);
  l.centre = vecLanes(next, stride);
  l.gap = scalarLanes(next, stride);
  l.weight = scalarLanes(next, stride);
  l.normal_force = scalarLanes(next, stride);
  l.elastic_energy = scalarLanes(next, stride);
  l.shear_energy = scalarLanes(next, stride);
  l.sliding = scalarLanes(next, stride);
  return l;
}

void turnCarriedShears(const SubLanes& l, std::size_t lanes, const Vec3& spin, double half_dt) {
  // Below this s . s the old and new normals are opposite (rotateShear): the shear is kept.
  constexpr double kOpposite = 1e-20;
  const double spin_x = spin.x(), spin_y = spin.y(), spin_z = spin.z();
  POLYDEM_LANES
  for (std::size_t i = 0; i < lanes; ++i) {
    const double nx = l.normal.x[i], ny = l.normal.y[i], nz = l.normal.z[i];
    const double fx = l.shear.x[i], fy = l.shear.y[i], fz = l.shear.z[i];
    // rotateShear: the reflection through the plane normal to s = n_old + n, then the
    // projection onto the new plane.
    const double sx = l.old_normal.x[i] + nx, sy = l.old_normal.y[i] + ny,
                 sz = l.old_normal.z[i] + nz;
    const double ss = (sx * sx + sy * sy) + sz * sz;
    const double k = 2.0 * ((fx * sx + fy * sy) + fz * sz) / ss;
    const bool turn = ss > kOpposite;
    const double tx = fx - k * sx, ty = fy - k * sy, tz = fz - k * sz;
    const double rx = turn ? tx : fx, ry = turn ? ty : fy, rz = turn ? tz : fz;
    const double rn = (rx * nx + ry * ny) + rz * nz;
    const double ux = rx - rn * nx, uy = ry - rn * ny, uz = rz - rn * nz;
    // spinShear: the Cayley rotation about n by 2 atan(t), t = dt/2 (spin . n).
    const double t = half_dt * ((spin_x * nx + spin_y * ny) + spin_z * nz);
    const double tt = t * t;
    const double keep = 1.0 - tt, cross = 2.0 * t, scale = 1.0 + tt;
    l.shear.x[i] = (keep * ux + cross * (ny * uz - nz * uy)) / scale;
    l.shear.y[i] = (keep * uy + cross * (nz * ux - nx * uz)) / scale;
    l.shear.z[i] = (keep * uz + cross * (nx * uy - ny * ux)) / scale;
  }
}

void springForces(const SubLanes& l, std::size_t lanes, const PairConstants& c) {
  const double xa_x = c.xa.x(), xa_y = c.xa.y(), xa_z = c.xa.z();
  const double va_x = c.va.x(), va_y = c.va.y(), va_z = c.va.z();
  const double wa_x = c.wa.x(), wa_y = c.wa.y(), wa_z = c.wa.z();
  const double xb_x = c.xb.x(), xb_y = c.xb.y(), xb_z = c.xb.z();
  const double vb_x = c.vb.x(), vb_y = c.vb.y(), vb_z = c.vb.z();
  const double wb_x = c.wb.x(), wb_y = c.wb.y(), wb_z = c.wb.z();
  const double kn = c.kn, ks = c.ks, dashpot = c.dashpot, dt = c.dt;
  const double tan_friction = c.tan_friction, cohesion = c.cohesion;
  POLYDEM_LANES
  for (std::size_t i = 0; i < lanes; ++i) {
    const double px = l.point.x[i], py = l.point.y[i], pz = l.point.z[i];
    const double nx = l.normal.x[i], ny = l.normal.y[i], nz = l.normal.z[i];
    const double w = l.weight[i], gap = l.gap[i];
    // Levers, and v_rel = (vA + wA x (p - xA)) - (vB + wB x (p - xB)) (Zhao eq. 31).
    const double ax = px - xa_x, ay = py - xa_y, az = pz - xa_z;
    const double bx = px - xb_x, by = py - xb_y, bz = pz - xb_z;
    const double vx = (va_x + (wa_y * az - wa_z * ay)) - (vb_x + (wb_y * bz - wb_z * by));
    const double vy = (va_y + (wa_z * ax - wa_x * az)) - (vb_y + (wb_z * bx - wb_x * bz));
    const double vz = (va_z + (wa_x * ay - wa_y * ax)) - (vb_z + (wb_x * by - wb_y * bx));
    const double v_normal = (vx * nx + vy * ny) + vz * nz;
    // Normal spring and the pair's dashpot, by weight; compression only.
    const double f_elastic = w * kn * gap;
    const double f_normal = std::max(f_elastic - w * dashpot * v_normal, 0.0);
    // Shear: the carried shear less ks_i dt v_t (Zhao eqs. 32-34), capped (Zhao eq. 35).
    const double ks_dt = w * ks * dt;
    double fx = l.shear.x[i] - ks_dt * (vx - v_normal * nx);
    double fy = l.shear.y[i] - ks_dt * (vy - v_normal * ny);
    double fz = l.shear.z[i] - ks_dt * (vz - v_normal * nz);
    const double cap = f_elastic * tan_friction + w * cohesion;
    const double magnitude = std::sqrt((fx * fx + fy * fy) + fz * fz);
    const double to_cap = cap / magnitude;
    const bool slides = magnitude > cap;
    fx = slides ? fx * to_cap : fx;
    fy = slides ? fy * to_cap : fy;
    fz = slides ? fz * to_cap : fz;
    l.shear.x[i] = fx;
    l.shear.y[i] = fy;
    l.shear.z[i] = fz;
    l.sliding[i] = slides ? 1.0 : 0.0;
    // The force on A, its torques about both centroids, the energies.
    const double gx = f_normal * nx + fx, gy = f_normal * ny + fy, gz = f_normal * nz + fz;
    l.force.x[i] = gx;
    l.force.y[i] = gy;
    l.force.z[i] = gz;
    l.torque_a.x[i] = ay * gz - az * gy;
    l.torque_a.y[i] = az * gx - ax * gz;
    l.torque_a.z[i] = ax * gy - ay * gx;
    l.torque_b.x[i] = by * gz - bz * gy;
    l.torque_b.y[i] = bz * gx - bx * gz;
    l.torque_b.z[i] = bx * gy - by * gx;
    l.normal_force[i] = f_normal;
    l.centre.x[i] = f_normal * px;
    l.centre.y[i] = f_normal * py;
    l.centre.z[i] = f_normal * pz;
    l.elastic_energy[i] = 0.5 * f_elastic * gap;
    l.shear_energy[i] = 0.5 * ((fx * fx + fy * fy) + fz * fz) / (w * ks);
  }
}

}  // namespace polydem::dynamics
