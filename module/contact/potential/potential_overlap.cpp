#include "polydem/contact/potential/potential_overlap.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "polydem/core/tolerance.h"

namespace polydem::contact::potential {

namespace {

// Whether every point of `loop` lies strictly beyond one side of the box [lo, hi].
bool outsideBox(std::span<const Vec3> corners, std::span<const int> loop, const Vec3& lo,
                const Vec3& hi) {
  for (int axis = 0; axis < 3; ++axis) {
    bool below = true, above = true;
    for (std::size_t k = 0; k < loop.size() && (below || above); ++k) {
      const double x = corners[loop[k]][axis];
      below = below && x < lo[axis];
      above = above && x > hi[axis];
    }
    if (below || above) return true;
  }
  return false;
}

}  // namespace

bool OverlapIntegrator::excludesBox(const Cell& cell, const Vec3& lo, const Vec3& hi) {
  const Vec3 centre = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
  for (const CellPlane& p : cell.planes) {
    if (p.normal.dot(centre) - p.offset - p.normal.cwiseAbs().dot(half) > 0.0) return true;
  }
  return false;
}

void OverlapIntegrator::loadPlanes(const Cell& other) {
  // Padded to an even count with a plane 0.x - 0 (never outside), so that the distances of a
  // corner go two at a time.
  const std::size_t m = other.planes.size(), padded = m + (m & 1);
  plane_x_.resize(padded);
  plane_y_.resize(padded);
  plane_z_.resize(padded);
  plane_offset_.resize(padded);
  for (std::size_t k = 0; k < m; ++k) {
    const CellPlane& p = other.planes[k];
    plane_x_[k] = p.normal.x();
    plane_y_[k] = p.normal.y();
    plane_z_[k] = p.normal.z();
    plane_offset_[k] = p.offset;
  }
  if (padded > m) plane_x_[m] = plane_y_[m] = plane_z_[m] = plane_offset_[m] = 0.0;
}

const std::uint64_t* OverlapIntegrator::outsideMask(const Cell& own, int v) {
  std::uint64_t* mask = outside_.data() + static_cast<std::size_t>(v) * words_;
  if (known_[v]) return mask;
  known_[v] = 1;
  // normal.x - offset with the products summed in the order of Eigen's dot, (n_x x + n_y y) +
  // n_z z: the same bits as CellPlane's, two planes at a time where SSE2 is there.
  const Vec3& x = own.corners[v];
  const std::size_t n = plane_x_.size();
  const double *px = plane_x_.data(), *py = plane_y_.data(), *pz = plane_z_.data(),
               *po = plane_offset_.data();
  for (std::size_t w = 0; w < words_; ++w) {
    std::uint64_t bits = 0;
    const std::size_t begin = 64 * w, end = std::min(n, begin + 64);
#if defined(__SSE2__)
    const __m128d x0 = _mm_set1_pd(x.x()), x1 = _mm_set1_pd(x.y()), x2 = _mm_set1_pd(x.z());
    const __m128d zero = _mm_setzero_pd();
    for (std::size_t k = begin; k < end; k += 2) {
      const __m128d xy =
          _mm_add_pd(_mm_mul_pd(_mm_loadu_pd(px + k), x0), _mm_mul_pd(_mm_loadu_pd(py + k), x1));
      const __m128d h =
          _mm_sub_pd(_mm_add_pd(xy, _mm_mul_pd(_mm_loadu_pd(pz + k), x2)), _mm_loadu_pd(po + k));
      bits |= static_cast<std::uint64_t>(_mm_movemask_pd(_mm_cmpgt_pd(h, zero))) << (k - begin);
    }
#else
    for (std::size_t k = begin; k < end; ++k) {
      const double h = (px[k] * x.x() + py[k] * x.y()) + pz[k] * x.z() - po[k];
      bits |= static_cast<std::uint64_t>(h > 0.0) << (k - begin);
    }
#endif
    mask[w] = bits;
  }
  return mask;
}

void OverlapIntegrator::clipFaces(const Cell& own, const Cell& other, bool on_a, const Vec3& lo,
                                  const Vec3& hi, const std::uint64_t* usable,
                                  std::uint64_t* reaching) {
  // For each corner of own, the set of the other's planes it lies outside of, computed once: a
  // face with all corners outside one plane is skipped, and the others are clipped by the planes
  // some corner is outside of, which is all it takes (a plane holding all corners of a face holds
  // the face).
  words_ = (other.planes.size() + 63) / 64;
  loadPlanes(other);
  outside_.resize(own.corners.size() * words_);
  known_.assign(own.corners.size(), 0);
  all_out_.resize(words_);
  any_out_.resize(words_);
  const std::size_t own_words = (own.planes.size() + 63) / 64;
  missed_.assign(own_words, 0);
  met_.assign(own_words, 0);
  for (const CellFace& face : own.faces) {
    const std::uint64_t plane_bit = std::uint64_t{1} << (face.plane & 63);
    missed_[face.plane >> 6] |= plane_bit;  // until the face is found to reach the other cell
    // The box holds the overlap: a face beyond one of its sides has no part in it.
    const std::span<const int> loop = own.loops.subspan(face.begin, face.end - face.begin);
    if (outsideBox(own.corners, loop, lo, hi)) continue;
    std::fill(all_out_.begin(), all_out_.end(), ~std::uint64_t{0});
    std::fill(any_out_.begin(), any_out_.end(), 0);
    for (int v : loop) {
      const std::uint64_t* mask = outsideMask(own, v);
      for (std::size_t w = 0; w < words_; ++w) {
        all_out_[w] &= mask[w];
        any_out_[w] |= mask[w];
      }
    }
    bool outside = false;
    for (std::size_t w = 0; w < words_; ++w) outside = outside || all_out_[w] != 0;
    if (outside) continue;
    met_[face.plane >> 6] |= plane_bit;
    if (usable != nullptr) {
      for (std::size_t w = 0; w < words_; ++w) any_out_[w] &= usable[w];
    }
    // Zhao steps 1-2 (eqs. 6-7): the part of this face inside the other cell. Clipped in space,
    // so that the clip sees the very distances the masks were made of (a face touching a plane
    // to round-off is kept or dropped consistently).
    clipper_.assign(own.corners, loop);
    bool inside = true;
    for (std::size_t w = 0; w < words_ && inside; ++w) {
      for (std::uint64_t bits = any_out_[w]; bits != 0 && inside; bits &= bits - 1) {
        const CellPlane& p = other.planes[64 * w + std::countr_zero(bits)];
        inside = clipper_.clip(p.normal, -p.offset);
      }
    }
    const auto poly = clipper_.polygon();
    if (!inside || poly.size() < 3) continue;
    // The piece in 2D coordinates of the face's plane about the mean of its corners, for the
    // region split and the integrals: coordinates and terms are then of the size of the piece
    // and its potential, with no cancellation of large numbers.
    const CellPlane& fp = own.planes[face.plane];
    PieceFrame frame;
    frame.origin = Vec3::Zero();
    for (const Vec3& x : poly) frame.origin += x;
    frame.origin /= static_cast<double>(poly.size());
    frame.e1 = fp.normal.unitOrthogonal();
    frame.e2 = fp.normal.cross(frame.e1);
    frame.normal = fp.normal;
    Piece piece;
    piece.begin = static_cast<int>(pool_.size());
    for (const Vec3& x : poly) {
      pool_.push_back(x);
      flat_pool_.push_back(frame.toPlane(x));
    }
    piece.end = static_cast<int>(pool_.size());
    piece.plane = face.plane;
    piece.on_a = on_a;
    piece.frame = frame;
    pieces_.push_back(piece);
  }
  // A plane with no face of own, or with a face that was not shown to miss the other cell, may
  // bound the overlap.
  if (reaching != nullptr) {
    for (std::size_t w = 0; w < own_words; ++w) reaching[w] = ~missed_[w] | met_[w];
  }
}

OverlapIntegrator::PoolSummary OverlapIntegrator::summarisePool() const {
  PoolSummary p{Vec3::Zero(), pool_.front(), pool_.front()};
  for (const Vec3& x : pool_) {
    p.mean += x;
    p.lo = p.lo.cwiseMin(x);
    p.hi = p.hi.cwiseMax(x);
  }
  p.mean /= static_cast<double>(pool_.size());
  return p;
}

double OverlapIntegrator::selectCandidates(const Cell& cell, const PoolSummary& pool,
                                           std::vector<int>& candidates,
                                           std::vector<char>& is_candidate) const {
  // phi = min_j term_j, each term linear, so over the overlap (the convex hull of pool_) phi <=
  // max over pool_ of term_k for any k =: bound, k the smallest term at the pool's mean; plane j
  // can be the minimum somewhere only if its smallest term over the overlap is <= bound, and the
  // pool's box bounds that from below. Each region of the piece split is clipped only by
  // candidates (EnvelopeIntegrator).
  const Vec3& mean = pool.mean;
  const std::size_t m = cell.planes.size();
  std::size_t best = 0;
  double best_term = cell.planes[0].term(mean);
  for (std::size_t j = 1; j < m; ++j) {
    const double t = cell.planes[j].term(mean);
    if (t < best_term) {
      best = j;
      best_term = t;
    }
  }
  double bound = -std::numeric_limits<double>::infinity();
  for (const Vec3& x : pool_) bound = std::max(bound, cell.planes[best].term(x));
  const Vec3 centre = 0.5 * (pool.lo + pool.hi), half = 0.5 * (pool.hi - pool.lo);
  candidates.clear();
  is_candidate.resize(m);
  for (std::size_t j = 0; j < m; ++j) {
    const CellPlane& p = cell.planes[j];
    const double box_low =
        (p.offset - p.normal.dot(centre) - p.normal.cwiseAbs().dot(half)) * p.inv_scale;
    is_candidate[j] = box_low <= bound;
    if (is_candidate[j]) candidates.push_back(static_cast<int>(j));
  }
  return bound;
}

PairInfo OverlapIntegrator::add(const Cell& a, const Cell& b, const Vec3& lo, const Vec3& hi,
                                OverlapSums& sums, std::vector<Vec3>& corners) {
  pool_.clear();
  flat_pool_.clear();
  pieces_.clear();
  PairInfo info;
  if (excludesBox(a, lo, hi) || excludesBox(b, lo, hi)) return info;
  // B's faces are clipped only by the planes of A whose faces may reach B, once a piece of A's
  // surface inside B shows that the overlap V is not empty. Exact: let x be a point of a face of
  // B inside A's planes but those of a set D, and y a point of V; along the segment x -> y (in B,
  // inside A's planes not in D) the first point inside A lies on a plane of D and inside A's other
  // planes: on a face of A, in B. So if every face of D misses B (beyond the box that holds V, or
  // every corner outside one plane of B), x is in A already and the clips by D cut nothing (the
  // same polygon), up to round-off at corners lying on such a plane.
  reach_a_.resize((a.planes.size() + 63) / 64);
  clipFaces(a, b, true, lo, hi, nullptr, reach_a_.data());
  clipFaces(b, a, false, lo, hi, pieces_.empty() ? nullptr : reach_a_.data(), nullptr);
  if (pieces_.empty()) return info;
  info.found = true;
  const PoolSummary pool = summarisePool();
  info.bound_a = selectCandidates(a, pool, candidates_a_, is_candidate_a_);
  info.bound_b = selectCandidates(b, pool, candidates_b_, is_candidate_b_);

  for (const Piece& piece : pieces_) {
    // On A's surface: n = A's face normal, phi_A = 0, integrand -n phi_B; on B's: n phi_A.
    const Cell& own = piece.on_a ? a : b;
    const Cell& other = piece.on_a ? b : a;
    const Vec3& normal = own.planes[piece.plane].normal;
    PieceIntegrals part;
    envelope_.integrate(
        std::span<const Vec2>(flat_pool_.data() + piece.begin, piece.end - piece.begin),
        piece.frame, other, piece.on_a ? candidates_b_ : candidates_a_,
        piece.on_a ? is_candidate_b_ : is_candidate_a_, part);
    // The first moment in space: integral of x phi = origin I + e1 I_u + e2 I_v.
    const PieceFrame& f = piece.frame;
    const Vec3 first_moment =
        part.integral * f.origin + part.first.x() * f.e1 + part.first.y() * f.e2;
    const double sign = piece.on_a ? -1.0 : 1.0;
    sums.force += (sign * part.integral) * normal;     // Zhao eq. 13
    sums.moment += sign * first_moment.cross(normal);  // Zhao eqs. 14-15
    sums.phi_integral += part.integral;
    sums.area += part.area;
    if (part.area > sums.largest_piece) {
      sums.largest_piece = part.area;
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
