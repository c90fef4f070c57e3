#include "contact/potential_overlap.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/tolerance.h"

namespace polydem::contact::potential {

namespace {

// Whether every point of `loop` lies strictly beyond one side of the box [lo, hi].
bool outsideBox(std::span<const Vec3> corners, std::span<const int> loop, const Vec3& lo,
                const Vec3& hi) {
  for (int axis = 0; axis < 3; ++axis) {
    bool below = true, above = true;
    for (int i : loop) {
      const double x = corners[i][axis];
      below = below && x < lo[axis];
      above = above && x > hi[axis];
    }
    if (below || above) return true;
  }
  return false;
}

}  // namespace

void integrateLinear(std::span<const Vec3> corners, std::span<const double> values,
                     const Vec3& normal, double& integral, Vec3& first_moment, double& area) {
  const std::size_t n = corners.size();
  const Vec3& x0 = corners[0];
  const double g0 = values[0];
  for (std::size_t k = 1; k + 1 < n; ++k) {
    const Vec3& x1 = corners[k];
    const Vec3& x2 = corners[k + 1];
    const double g1 = values[k], g2 = values[k + 1];
    // Signed area about the known normal: exact orientation, no square root.
    const double a = 0.5 * normal.dot((x1 - x0).cross(x2 - x0));
    const double gs = g0 + g1 + g2;
    area += a;
    integral += a * gs / 3.0;  // Zhao eq. 23: area times the mean corner value
    first_moment += (a / 12.0) * (g0 * x0 + g1 * x1 + g2 * x2 + gs * (x0 + x1 + x2));  // eqs. 24-25
  }
}

void OverlapIntegrator::clipFaces(const Cell& own, const Cell& other, bool on_a, const Vec3& lo,
                                  const Vec3& hi) {
  for (const CellFace& face : own.faces) {
    const std::span<const int> loop = own.loops.subspan(face.begin, face.end - face.begin);
    if (outsideBox(own.corners, loop, lo, hi)) continue;
    // Zhao steps 1-2 (eqs. 6-7): the part of this face inside the other cell.
    clipper_.assign(own.corners, loop);
    bool inside = true;
    for (const CellPlane& p : other.planes) {
      if (!clipper_.clip(p.normal, -p.offset)) {
        inside = false;
        break;
      }
    }
    const auto& poly = clipper_.polygon();
    if (!inside || poly.size() < 3) continue;
    Piece piece;
    piece.begin = static_cast<int>(pool_.size());
    pool_.insert(pool_.end(), poly.begin(), poly.end());
    piece.end = static_cast<int>(pool_.size());
    piece.plane = face.plane;
    piece.on_a = on_a;
    pieces_.push_back(piece);
  }
}

double OverlapIntegrator::selectCandidates(const Cell& cell, std::vector<int>& candidates) {
  // phi = min_j term_j. Over the overlap (whose corners are all in pool_), term_j lies in
  // [lo_j, hi_j] (linear: extremes at corners), so phi <= min_j hi_j =: bound, and plane j can
  // be the minimum somewhere only if lo_j <= bound. Shallow contacts keep one or two planes.
  const std::size_t m = cell.planes.size();
  lo_term_.assign(m, std::numeric_limits<double>::infinity());
  hi_term_.assign(m, -std::numeric_limits<double>::infinity());
  for (std::size_t j = 0; j < m; ++j) {
    const CellPlane& p = cell.planes[j];
    for (const Vec3& x : pool_) {
      const double t = p.term(x);
      lo_term_[j] = std::min(lo_term_[j], t);
      hi_term_[j] = std::max(hi_term_[j], t);
    }
  }
  const double bound = *std::min_element(hi_term_.begin(), hi_term_.end());
  candidates.clear();
  for (std::size_t j = 0; j < m; ++j) {
    if (lo_term_[j] <= bound) candidates.push_back(static_cast<int>(j));
  }
  return bound;
}

void OverlapIntegrator::integratePiece(const Piece& piece, const Vec3& normal, const Cell& cell,
                                       const std::vector<int>& candidates, double& integral,
                                       Vec3& first_moment, double& area) {
  const std::span<const Vec3> corners(pool_.data() + piece.begin, piece.end - piece.begin);
  // Integrates plane j's term over the polygon `poly` (Zhao eqs. 9-12: phi is linear there).
  auto integrateTerm = [&](std::span<const Vec3> poly, int j) {
    const CellPlane& p = cell.planes[j];
    values_.resize(poly.size());
    for (std::size_t i = 0; i < poly.size(); ++i) values_[i] = p.term(poly[i]);
    integrateLinear(poly, values_, normal, integral, first_moment, area);
  };
  // If one plane's term is the smallest at every corner, it is the smallest on the whole piece
  // (term differences are linear): the piece lies in one region.
  int single = candidates.front();
  for (int j : candidates) {
    if (cell.planes[j].term(corners[0]) < cell.planes[single].term(corners[0])) single = j;
  }
  for (std::size_t i = 1; i < corners.size() && single >= 0 && candidates.size() > 1; ++i) {
    const double ts = cell.planes[single].term(corners[i]);
    for (int j : candidates) {
      if (cell.planes[j].term(corners[i]) < ts) {
        single = -1;
        break;
      }
    }
  }
  if (single >= 0) {
    integrateTerm(corners, single);
    return;
  }
  // Zhao step 2 (eqs. 7-8): the piece split by the cell's regions; region j is where term j is
  // the smallest: clip by term_j - term_k <= 0 for every other candidate k.
  for (int j : candidates) {
    const CellPlane& pj = cell.planes[j];
    clipper_.assign(corners);
    bool left = true;
    for (int k : candidates) {
      if (k == j) continue;
      const CellPlane& pk = cell.planes[k];
      const Vec3 w = pk.normal * pk.inv_scale - pj.normal * pj.inv_scale;
      const double c = pj.offset * pj.inv_scale - pk.offset * pk.inv_scale;
      if (!clipper_.clip(w, c)) {
        left = false;
        break;
      }
    }
    if (left && clipper_.polygon().size() >= 3) integrateTerm(clipper_.polygon(), j);
  }
}

PairInfo OverlapIntegrator::add(const Cell& a, const Cell& b, const Vec3& lo, const Vec3& hi,
                                OverlapSums& sums, std::vector<Vec3>& corners) {
  pool_.clear();
  pieces_.clear();
  clipFaces(a, b, true, lo, hi);
  clipFaces(b, a, false, lo, hi);
  PairInfo info;
  if (pieces_.empty()) return info;
  info.found = true;
  info.bound_a = selectCandidates(a, candidates_a_);
  info.bound_b = selectCandidates(b, candidates_b_);

  for (const Piece& piece : pieces_) {
    // On A's surface: n = A's face normal, phi_A = 0, integrand -n phi_B; on B's: n phi_A.
    const Cell& own = piece.on_a ? a : b;
    const Cell& other = piece.on_a ? b : a;
    const Vec3& normal = own.planes[piece.plane].normal;
    double integral = 0.0, area = 0.0;
    Vec3 first_moment = Vec3::Zero();
    integratePiece(piece, normal, other, piece.on_a ? candidates_b_ : candidates_a_, integral,
                   first_moment, area);
    const double sign = piece.on_a ? -1.0 : 1.0;
    sums.force += (sign * integral) * normal;          // Zhao eq. 13
    sums.moment += sign * first_moment.cross(normal);  // Zhao eqs. 14-15
    sums.phi_integral += integral;
    sums.area += area;
    if (area > sums.largest_piece) {
      sums.largest_piece = area;
      sums.largest_normal = normal;
      sums.largest_offset = own.planes[piece.plane].offset;
    }
  }
  corners.insert(corners.end(), pool_.begin(), pool_.end());
  return info;
}

void boundingBox(std::span<const Vec3> points, Vec3& lo, Vec3& hi) {
  lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  hi = -lo;
  for (const Vec3& p : points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
}

PotentialResult finishContact(const OverlapSums& sums, std::span<const Vec3> corners,
                              const Vec3& origin, double length_scale,
                              const Vec3& fallback_normal) {
  PotentialResult r;
  Contact& c = r.contact;
  c.model = ForceModel::kPotential;
  if (corners.empty() || sums.largest_piece <= 0.0) return r;
  // A flat overlap (touching faces, depth 0) is no contact: every corner on one plane.
  double thickness = 0.0;
  for (const Vec3& x : corners) {
    thickness = std::max(thickness, std::abs(sums.largest_normal.dot(x) - sums.largest_offset));
  }
  if (thickness <= absTol(length_scale, RelTol::kPlane)) return r;
  c.touching = true;

  const Vec3& f = sums.force;
  const double fn = f.norm();
  // The force vanishes when both potentials vanish on the whole boundary (identical bodies) or
  // cancel (one body centred in the other): no direction, status kDegenerate.
  const bool no_potential = sums.phi_integral <= 1e-12 * sums.area;
  const bool cancelled = fn <= 1e-12 * sums.phi_integral;
  Vec3 point_rel = Vec3::Zero();
  if (no_potential || cancelled) {
    c.normal = fallback_normal;
    c.potential = 0.0;
    c.status = Status::kDegenerate;
    for (const Vec3& x : corners) point_rel += x;
    point_rel /= static_cast<double>(corners.size());
  } else {
    c.normal = f / fn;
    c.potential = fn;
    // Zhao eq. 29 generalised: the line of action carries the moment; its point closest to the
    // origin is f x M / |f|^2. Along the line, take the middle of the overlap's extent.
    point_rel = f.cross(sums.moment) / (fn * fn);
  }
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const Vec3& x : corners) {
    const double s = c.normal.dot(x);
    lo = std::min(lo, s);
    hi = std::max(hi, s);
  }
  c.depth = hi - lo;
  if (c.status != Status::kDegenerate) {
    point_rel += (0.5 * (lo + hi) - c.normal.dot(point_rel)) * c.normal;
  }
  c.point = origin + point_rel;
  r.force = f;
  r.moment = sums.moment - point_rel.cross(f);
  r.torsion = r.moment.dot(c.normal);
  return r;
}

}  // namespace polydem::contact::potential
