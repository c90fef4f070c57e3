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

bool OverlapIntegrator::activePlanes(const Cell& cell, const Vec3& lo, const Vec3& hi,
                                     std::vector<int>& active) {
  // A plane that holds the whole box cannot cut anything in it; one that excludes the whole box
  // leaves nothing (no overlap).
  const Vec3 centre = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
  active.clear();
  for (std::size_t j = 0; j < cell.planes.size(); ++j) {
    const CellPlane& p = cell.planes[j];
    const double mid = p.normal.dot(centre) - p.offset;
    const double reach = p.normal.cwiseAbs().dot(half);
    if (mid - reach > 0.0) return false;
    if (mid + reach > 0.0) active.push_back(static_cast<int>(j));
  }
  return true;
}

void OverlapIntegrator::clipFaces(const Cell& own, const Cell& other,
                                  const std::vector<int>& other_active, bool on_a, const Vec3& lo,
                                  const Vec3& hi) {
  // Signed distances of own's corners to the other's active planes, each computed once: a face
  // with all corners outside one plane is skipped, and only planes that separate its corners
  // are clipped by (a plane holding all corners of a face holds the face).
  const std::size_t n_active = other_active.size();
  distance_.resize(own.corners.size() * n_active);
  known_.assign(own.corners.size(), 0);
  for (const CellFace& face : own.faces) {
    const std::span<const int> loop = own.loops.subspan(face.begin, face.end - face.begin);
    if (outsideBox(own.corners, loop, lo, hi)) continue;
    for (int v : loop) {
      if (known_[v]) continue;
      known_[v] = 1;
      for (std::size_t k = 0; k < n_active; ++k) {
        const CellPlane& p = other.planes[other_active[k]];
        distance_[v * n_active + k] = p.normal.dot(own.corners[v]) - p.offset;
      }
    }
    cut_.clear();
    bool outside = false;
    for (std::size_t k = 0; k < n_active && !outside; ++k) {
      bool all_out = true, any_out = false;
      for (int v : loop) {
        const bool out = distance_[v * n_active + k] > 0.0;
        all_out = all_out && out;
        any_out = any_out || out;
      }
      outside = all_out;
      if (any_out) cut_.push_back(other_active[k]);
    }
    if (outside) continue;
    // Zhao steps 1-2 (eqs. 6-7): the part of this face inside the other cell. The overlap lies in
    // the box, so clipping by it first changes nothing but drops far parts early.
    clipper_.assign(own.corners, loop);
    bool inside = true;
    for (int axis = 0; axis < 3 && inside; ++axis) {
      inside =
          clipper_.clip(Vec3::Unit(axis), -hi[axis]) && clipper_.clip(-Vec3::Unit(axis), lo[axis]);
    }
    for (std::size_t k = 0; k < cut_.size() && inside; ++k) {
      const CellPlane& p = other.planes[cut_[k]];
      inside = clipper_.clip(p.normal, -p.offset);
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
  // phi = min_j term_j, each term linear, so over the overlap (whose corners are all in pool_)
  // phi <= max over pool_ of term_k for any k =: bound; plane j can be the minimum somewhere only
  // if its smallest term over pool_ is <= bound. k is the smallest term at the pool's mean; the
  // pool's box gives a cheap lower bound of each plane's smallest term first. Shallow contacts
  // keep one or two planes.
  Vec3 mean = Vec3::Zero(), lo = pool_.front(), hi = pool_.front();
  for (const Vec3& x : pool_) {
    mean += x;
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  mean /= static_cast<double>(pool_.size());
  const std::size_t m = cell.planes.size();
  std::size_t best = 0;
  for (std::size_t j = 1; j < m; ++j) {
    if (cell.planes[j].term(mean) < cell.planes[best].term(mean)) best = j;
  }
  double bound = -std::numeric_limits<double>::infinity();
  for (const Vec3& x : pool_) bound = std::max(bound, cell.planes[best].term(x));
  const Vec3 centre = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
  candidates.clear();
  for (std::size_t j = 0; j < m; ++j) {
    const CellPlane& p = cell.planes[j];
    const double box_low =
        (p.offset - p.normal.dot(centre) - p.normal.cwiseAbs().dot(half)) * p.inv_scale;
    if (box_low > bound) continue;
    double low = std::numeric_limits<double>::infinity();
    for (const Vec3& x : pool_) low = std::min(low, p.term(x));
    if (low <= bound) candidates.push_back(static_cast<int>(j));
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
  PairInfo info;
  if (!activePlanes(a, lo, hi, active_a_) || !activePlanes(b, lo, hi, active_b_)) return info;
  clipFaces(a, b, active_b_, true, lo, hi);
  clipFaces(b, a, active_a_, false, lo, hi);
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

namespace {

void boundingBox(std::span<const Vec3> points, Vec3& lo, Vec3& hi) {
  lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  hi = -lo;
  for (const Vec3& p : points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
}

}  // namespace

bool commonBox(std::span<const Vec3> a, std::span<const Vec3> b, Vec3& lo, Vec3& hi) {
  Vec3 lo_a, hi_a, lo_b, hi_b;
  boundingBox(a, lo_a, hi_a);
  boundingBox(b, lo_b, hi_b);
  lo = lo_a.cwiseMax(lo_b);
  hi = hi_a.cwiseMin(hi_b);
  return !(lo.array() >= hi.array()).any();
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
