#include "polydem/contact/potential/potential_envelope.h"

#include <algorithm>

namespace polydem::contact::potential {

namespace {

double cross(const Vec2& a, const Vec2& b) {
  return a.x() * b.y() - a.y() * b.x();
}

double polygonArea(std::span<const Vec2> corners) {
  double twice = 0.0;
  for (std::size_t k = 1; k + 1 < corners.size(); ++k) {
    twice += cross(corners[k] - corners[0], corners[k + 1] - corners[0]);
  }
  return 0.5 * twice;
}

}  // namespace

void integrateLinear(std::span<const Vec2> corners, std::span<const double> values,
                     PieceIntegrals& out) {
  const std::size_t n = corners.size();
  const Vec2& y0 = corners[0];
  const double g0 = values[0];
  for (std::size_t k = 1; k + 1 < n; ++k) {
    const Vec2& y1 = corners[k];
    const Vec2& y2 = corners[k + 1];
    const double g1 = values[k], g2 = values[k + 1];
    // Signed area: exact orientation, no square root.
    const double a = 0.5 * cross(y1 - y0, y2 - y0);
    const double gs = g0 + g1 + g2;
    out.area += a;
    out.integral += a * gs / 3.0;  // Zhao eq. 23: area times the mean corner value
    out.first += (a / 12.0) * (g0 * y0 + g1 * y1 + g2 * y2 + gs * (y0 + y1 + y2));  // eqs. 24-25
  }
}

const EnvelopeIntegrator::Term& EnvelopeIntegrator::makeTerm(int l) {
  Term& t = terms_[l];
  stamp_[l] = piece_;
  // term_l(x) = (offset - n.x) s with x = origin + u e1 + v e2.
  const CellPlane& p = cell_->planes[l];
  t.a = (p.offset - p.normal.dot(frame_->origin)) * p.inv_scale;
  t.g = Vec2(-p.normal.dot(frame_->e1) * p.inv_scale, -p.normal.dot(frame_->e2) * p.inv_scale);
  return t;
}

void EnvelopeIntegrator::reserve(std::size_t n) {
  if (poly_.size() >= n) return;
  const std::size_t size = 2 * n + 8;
  poly_.resize(size);
  next_.resize(size);
  labels_.resize(size);
  next_labels_.resize(size);
  h_.resize(size);
  region_values_.resize(size);
}

inline bool EnvelopeIntegrator::clip(const Vec2& g, double c, int label) {
  // The buffers hold the piece plus one corner per cut (reserved by buildRegion).
  const std::size_t n = poly_n_;
  double* h = h_.data();
  const Vec2* poly = poly_.data();
  std::size_t n_out = 0;
  for (std::size_t i = 0; i < n; ++i) {
    h[i] = g.x() * poly[i].x() + g.y() * poly[i].y() + c;
    n_out += h[i] > 0.0;
  }
  return n_out == 0 || cut(n_out, label);
}

bool EnvelopeIntegrator::cut(std::size_t n_out, int label) {
  const std::size_t n = poly_n_;
  if (n_out == n) {
    poly_n_ = 0;
    return false;
  }
  const double* h = h_.data();
  const Vec2* poly = poly_.data();
  // Sutherland-Hodgman as geometry::ConvexPolygonClipper (corners on the line kept, no new
  // corner next to them), carrying the edge labels: a kept edge keeps its label, the new edge
  // gets `label`.
  Vec2* out = next_.data();
  int* out_labels = next_labels_.data();
  const int* labels = labels_.data();
  std::size_t m = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t j = i + 1 == n ? 0 : i + 1;
    const double hi = h[i], hj = h[j];
    if (hi <= 0.0) {
      out[m] = poly[i];
      out_labels[m++] = hj > 0.0 && hi == 0.0 ? label : labels[i];
      if (hi < 0.0 && hj > 0.0) {
        out[m] = poly[i] + (hi / (hi - hj)) * (poly[j] - poly[i]);
        out_labels[m++] = label;
      }
    } else if (hj < 0.0) {
      out[m] = poly[i] + (hi / (hi - hj)) * (poly[j] - poly[i]);
      out_labels[m++] = labels[i];
    }
  }
  poly_.swap(next_);
  labels_.swap(next_labels_);
  poly_n_ = m;
  return true;
}

EnvelopeIntegrator::Sides EnvelopeIntegrator::sides(int k) const {
  Sides s;
  if (!located_) return s;
  const RegionFacets& f = cell_->facets;
  const int first = f.corner_begin[k], count = f.corner_begin[k + 1] - first;
  if (count > RegionFacets::kMaskedCorners) return s;
  s.above = s.below = 0;
  const double tol = f.tolerance;
  for (int i = 0; i < count; ++i) {
    const double h = h0_ + dh_.dot(f.corners[first + i]);
    s.above |= static_cast<std::uint64_t>(h >= -tol) << i;
    s.below |= static_cast<std::uint64_t>(h <= tol) << i;
  }
  return s;
}

bool EnvelopeIntegrator::buildRegion(int k, std::span<const int> others) {
  // A region whose corners all lie beyond the piece's plane on one side misses the piece.
  const Sides s = sides(k);
  if (s.above == 0 || s.below == 0) return false;
  const std::uint64_t* facets =
      located_ ? cell_->facets.masks.data() + cell_->region_begin[k] : nullptr;
  const std::size_t n = corners_.size();
  reserve(n + others.size());
  std::copy(corners_.begin(), corners_.end(), poly_.begin());
  std::fill_n(labels_.begin(), n, -1);
  poly_n_ = n;
  const Term tk = term(k);
  for (std::size_t i = 0; i < others.size(); ++i) {
    const int l = others[i];
    // A neighbour that is no candidate of the pair bounds region k nowhere in the overlap, when
    // region k meets the piece (the walk visits only such k): on the segment of the piece from
    // a point of region k to a point outside, the first bisector crossed is that of a
    // neighbour m with term_m = term_k = phi <= the pair's bound at the crossing, so m is a
    // candidate, and term_k > term_m from there on: m's clip removes the point already.
    if (l == k || (skip_non_candidates_ && !is_candidate_[l])) continue;
    // Nor does a neighbour whose facet with k misses the piece's plane (within the tolerance),
    // wherever region k comes within the tolerance of that plane (the test above): from a point
    // x0 of region k that near the plane to a point y of the piece outside region k, the segment
    // leaves region k at a point x of its facet with some m, no farther from the plane than x0;
    // so m's facet meets the plane, m is clipped, and term_k > term_m at y, since term_k -
    // term_m is linear along the segment, zero at x and positive just past it. The clips of
    // the facets that meet the plane thus cut region k out exactly.
    if (facets != nullptr && ((facets[i] & s.above) == 0 || (facets[i] & s.below) == 0)) continue;
    // Zhao eq. 8: term_k - term_l <= 0 (a plane below term_k at no corner leaves it whole).
    const Term& tl = term(l);
    if (!clip(tk.g - tl.g, tk.a - tl.a, l)) return false;
  }
  return poly_n_ >= 3;
}

std::span<const int> EnvelopeIntegrator::others(int k) const {
  if (cell_->region_begin.empty()) return candidates_;
  return cell_->region_neighbours.subspan(cell_->region_begin[k],
                                          cell_->region_begin[k + 1] - cell_->region_begin[k]);
}

double EnvelopeIntegrator::walk(std::size_t from, PieceIntegrals& out) {
  double area = 0.0;
  for (std::size_t q = from; q < queue_.size(); ++q) {
    const int k = queue_[q];
    if (!buildRegion(k, others(k))) continue;
    // Zhao eqs. 9-12, 23-25: phi = term_k is linear on the region.
    const Term& t = terms_[k];
    const std::span<const Vec2> region(poly_.data(), poly_n_);
    for (std::size_t i = 0; i < poly_n_; ++i) region_values_[i] = t.a + t.g.dot(region[i]);
    const double before = out.area;
    integrateLinear(region, std::span<const double>(region_values_.data(), poly_n_), out);
    area += out.area - before;
    for (std::size_t i = 0; i < poly_n_; ++i) {
      const int l = labels_[i];
      if (l >= 0 && queued_[l] != piece_) {
        queued_[l] = piece_;
        queue_.push_back(l);
      }
    }
  }
  return area;
}

void EnvelopeIntegrator::integrate(std::span<const Vec2> corners, const PieceFrame& frame,
                                   const Cell& cell, std::span<const int> planes,
                                   std::span<const char> is_candidate, PieceIntegrals& out) {
  corners_ = corners;
  frame_ = &frame;
  cell_ = &cell;
  is_candidate_ = is_candidate;
  // The piece's plane at the basis corners of the cell's located regions.
  located_ = !cell.facets.corner_begin.empty() && !cell.region_begin.empty();
  if (located_) {
    const auto h = [&](int i) {
      return frame.normal.dot(cell.corners[cell.facets.basis[i]] - frame.origin);
    };
    h0_ = h(0);
    dh_ = Vec3(h(1) - h0_, h(2) - h0_, h(3) - h0_);
  }
  ++piece_;  // a fresh stamp: no term is made yet
  const std::size_t m = cell.planes.size();
  if (stamp_.size() < m) {
    stamp_.resize(m, 0);
    queued_.resize(m, 0);
    terms_.resize(m);
  }
  Vec2 mean = Vec2::Zero();
  for (const Vec2& y : corners) mean += y;
  mean /= static_cast<double>(corners.size());
  // Start at the plane smallest at the piece's centre (`planes` holds every plane that is the
  // smallest somewhere in the overlap).
  const Vec3 centre = frame.toSpace(mean);
  int best = planes[0];
  double best_term = cell.planes[best].term(centre);
  for (int j : planes) {
    const double t = cell.planes[j].term(centre);
    if (t < best_term) {
      best = j;
      best_term = t;
    }
  }
  if (cell.region_begin.empty()) {
    // No partition: any candidate may bound any region.
    candidates_.assign(planes.begin(), planes.end());
  }
  queue_.assign(1, best);
  queued_[best] = piece_;
  skip_non_candidates_ = true;
  double covered = walk(0, out);
  // The walk crosses from region to region along edges. Should it have missed one (two
  // bisectors meeting the piece's plane in the same line), the area says so: then every plane
  // not yet tried gets its region built.
  if (covered < polygonArea(corners) * (1.0 - 1e-12)) {
    const std::size_t tried = queue_.size();
    for (int j : planes) {
      if (queued_[j] != piece_) {
        queued_[j] = piece_;
        queue_.push_back(j);
      }
    }
    // These regions may miss the piece: clip them by every neighbour.
    skip_non_candidates_ = false;
    walk(tried, out);
  }
}

}  // namespace polydem::contact::potential
