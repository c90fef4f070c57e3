#include "polydem/geometry/face_regions.h"

#include <algorithm>
#include <cmath>
#include <mutex>

#include "polydem/core/types.h"
#include "polydem/geometry/convex_polyhedron.h"

namespace polydem::geometry {

namespace {

// A number that increases with the angle of (x, y) as atan2 does (on (-2, 2]), without trig.
double pseudoAngle(double x, double y) {
  const double r = std::abs(x) + std::abs(y);
  if (r == 0.0) return 0.0;
  const double t = x / r;  // from 1 (angle 0) to -1 (angle pi)
  return y >= 0.0 ? 1.0 - t : t - 1.0;
}

// A convex polytope as its faces (polygons, corners in order), in flat buffers reused from clip
// to clip.
class Polytope {
 public:
  // Starts again from the prism over face k, `depth` deep inward (the buffers keep their
  // capacity). Region k lies in it: no point of the polyhedron is deeper than the inradius below
  // any face, and the bisectors through k's edges lean over k (dihedral angles are below 180
  // degrees), so the region stays over the face.
  void reset(const ConvexPolyhedron& p, int k, double depth) {
    pts_.clear();
    ends_.clear();
    const Face& face = p.faces()[k];
    const Vec3 down = -depth * face.normal;
    const std::size_t n = face.vertices.size();
    for (int v : face.vertices) pts_.push_back(p.vertices()[v]);
    ends_.push_back(static_cast<int>(pts_.size()));
    for (std::size_t i = n; i-- > 0;) pts_.push_back(p.vertices()[face.vertices[i]] + down);
    ends_.push_back(static_cast<int>(pts_.size()));
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3& a = p.vertices()[face.vertices[i]];
      const Vec3& b = p.vertices()[face.vertices[(i + 1) % n]];
      pts_.insert(pts_.end(), {b, a, a + down, b + down});
      ends_.push_back(static_cast<int>(pts_.size()));
    }
    updateSphere();
  }

  // Keeps the part where w.x + c <= 0 and closes it with the cap polygon in the plane.
  void clip(const Vec3& w, double c, double merge) {
    // The polytope's bounding sphere decides most planes without looking at the corners.
    if (w.dot(centre_) + c + w.norm() * radius_ <= 0.0) return;
    h_.resize(pts_.size());
    bool cuts = false;
    for (std::size_t i = 0; i < pts_.size(); ++i) {
      h_[i] = w.dot(pts_[i]) + c;
      cuts = cuts || h_[i] > 0.0;
    }
    if (!cuts) return;
    next_pts_.clear();
    next_ends_.clear();
    cap_.clear();
    int begin = 0;
    for (int end : ends_) {
      const std::size_t first = next_pts_.size();
      for (int i = begin; i < end; ++i) {
        const int j = i + 1 == end ? begin : i + 1;
        if (h_[i] <= 0.0) next_pts_.push_back(pts_[i]);
        if (h_[i] == 0.0) cap_.push_back(pts_[i]);
        if ((h_[i] < 0.0 && h_[j] > 0.0) || (h_[i] > 0.0 && h_[j] < 0.0)) {
          const Vec3 x = pts_[i] + (h_[i] / (h_[i] - h_[j])) * (pts_[j] - pts_[i]);
          next_pts_.push_back(x);
          cap_.push_back(x);
        }
      }
      if (next_pts_.size() - first >= 3) {
        next_ends_.push_back(static_cast<int>(next_pts_.size()));
      } else {
        next_pts_.resize(first);
      }
      begin = end;
    }
    addCap(w, merge);
    pts_.swap(next_pts_);
    ends_.swap(next_ends_);
    updateSphere();
  }

  const std::vector<Vec3>& corners() const { return pts_; }

 private:
  void updateSphere() {
    centre_ = Vec3::Zero();
    for (const Vec3& x : pts_) centre_ += x;
    centre_ /= static_cast<double>(std::max<std::size_t>(pts_.size(), 1));
    radius_ = 0.0;
    for (const Vec3& x : pts_) radius_ = std::max(radius_, (x - centre_).norm());
  }

  // The cap: the new points ordered counter-clockwise about w, points within `merge` of the
  // previous one dropped.
  void addCap(const Vec3& w, double merge) {
    if (cap_.size() < 3) return;
    Vec3 centre = Vec3::Zero();
    for (const Vec3& p : cap_) centre += p;
    centre /= static_cast<double>(cap_.size());
    const Vec3 axis = w.normalized();
    const Vec3 e1 = axis.unitOrthogonal(), e2 = axis.cross(e1);
    keyed_.clear();
    for (const Vec3& p : cap_) {
      keyed_.emplace_back(pseudoAngle((p - centre).dot(e1), (p - centre).dot(e2)), p);
    }
    std::sort(keyed_.begin(), keyed_.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    const std::size_t first = next_pts_.size();
    for (const auto& [angle, p] : keyed_) {
      if (next_pts_.size() == first || (p - next_pts_.back()).norm() > merge) {
        next_pts_.push_back(p);
      }
    }
    while (next_pts_.size() > first + 1 && (next_pts_[first] - next_pts_.back()).norm() <= merge) {
      next_pts_.pop_back();
    }
    if (next_pts_.size() - first >= 3) {
      next_ends_.push_back(static_cast<int>(next_pts_.size()));
    } else {
      next_pts_.resize(first);
    }
  }

  std::vector<Vec3> pts_, next_pts_, cap_;
  std::vector<int> ends_, next_ends_;
  std::vector<double> h_;
  std::vector<std::pair<double, Vec3>> keyed_;
  Vec3 centre_ = Vec3::Zero();
  double radius_ = 0.0;
};

// Four vertices spanning the shape: vertex 0, the vertex farthest from it, the one farthest from
// their line, the one farthest from the plane of the three (a well-conditioned affine basis).
std::array<int, 4> affineBasis(const std::vector<Vec3>& v) {
  std::array<int, 4> b{0, 0, 0, 0};
  auto farthest = [&](auto distance) {
    int best = 0;
    double most = -1.0;
    for (std::size_t i = 0; i < v.size(); ++i) {
      const double d = distance(v[i]);
      if (d > most) {
        most = d;
        best = static_cast<int>(i);
      }
    }
    return best;
  };
  b[1] = farthest([&](const Vec3& x) { return (x - v[b[0]]).squaredNorm(); });
  const Vec3 axis = (v[b[1]] - v[b[0]]).normalized();
  b[2] = farthest([&](const Vec3& x) { return axis.cross(x - v[b[0]]).squaredNorm(); });
  const Vec3 normal = axis.cross(v[b[2]] - v[b[0]]);
  b[3] = farthest([&](const Vec3& x) { return std::abs(normal.dot(x - v[b[0]])); });
  return b;
}

// What is kept of one region: its neighbours, its corners and which lie on each facet.
struct RegionOut {
  std::vector<int>& neighbours;
  std::vector<Vec3>& corners;  // in the shape's frame (turned into affine coordinates later)
  std::vector<std::uint64_t>& facets;
};

// The neighbours of face k's region: clip the prism over face k by d_k <= d_l for every l (the
// faces sharing an edge with k first: they shrink the polytope most), then keep every l whose
// bisector comes within `touch` of what is left, with the corners on it.
void buildRegion(const ConvexPolyhedron& p, int k, double merge, double touch, Polytope& polytope,
                 std::vector<int>& order, RegionOut out) {
  const auto& faces = p.faces();
  const int m = static_cast<int>(faces.size());
  // Region k is no deeper than the inradius below face k; a little more keeps round-off out.
  polytope.reset(p, k, 1.01 * p.inradius() + 1e-9 * p.lengthScale());
  order.clear();
  for (int e : faces[k].edges) {
    const Edge& edge = p.edges()[e];
    order.push_back(edge.f0 == k ? edge.f1 : edge.f0);
  }
  const std::size_t adjacent = order.size();
  for (int l = 0; l < m; ++l) {
    if (l != k &&
        std::find(order.begin(), order.begin() + adjacent, l) == order.begin() + adjacent) {
      order.push_back(l);
    }
  }
  // d_k - d_l = (n_l - n_k).x + (o_k - o_l) <= 0.
  const Face& fk = faces[k];
  for (std::size_t i = 0; i < order.size(); ++i) {
    const Face& fl = faces[order[i]];
    polytope.clip(fl.normal - fk.normal, fk.offset - fl.offset, merge);
  }
  // The polytope lists a corner once per face it bounds: keep one of each (a near twin within
  // 1e-10 of the length scale moves a facet's hull by far less than the kernel's tolerance).
  const std::size_t first = out.corners.size();
  const double twin = 1e-10 * p.lengthScale();
  for (const Vec3& x : polytope.corners()) {
    const bool seen = std::any_of(out.corners.begin() + first, out.corners.end(),
                                  [&](const Vec3& y) { return (x - y).norm() <= twin; });
    if (!seen) out.corners.push_back(x);
  }
  const std::span<const Vec3> corners(out.corners.data() + first, out.corners.size() - first);
  const bool masked = corners.size() <= FaceRegions::kMaskedCorners;
  for (int l = 0; l < m; ++l) {
    if (l == k) continue;
    const Vec3 w = faces[l].normal - fk.normal;
    const double c = fk.offset - faces[l].offset;
    double highest = -INFINITY;
    std::uint64_t on = 0;
    for (std::size_t i = 0; i < corners.size(); ++i) {
      const double h = w.dot(corners[i]) + c;
      highest = std::max(highest, h);
      if (masked && h >= -touch) on |= std::uint64_t{1} << i;
    }
    if (highest < -touch) continue;
    out.neighbours.push_back(l);
    out.facets.push_back(masked ? on : ~std::uint64_t{0});
  }
}

std::mutex& buildMutex() {
  static std::mutex m;
  return m;
}

}  // namespace

FaceRegions computeFaceRegions(const ConvexPolyhedron& polyhedron) {
  const double scale = polyhedron.lengthScale();
  FaceRegions regions;
  regions.begin.push_back(0);
  const int m = static_cast<int>(polyhedron.faces().size());
  Polytope polytope;
  std::vector<int> order;
  regions.corner_begin.push_back(0);
  for (int k = 0; k < m; ++k) {
    buildRegion(polyhedron, k, 1e-12 * scale, 1e-9 * scale, polytope, order,
                {regions.neighbours, regions.corners, regions.facets});
    regions.begin.push_back(static_cast<int>(regions.neighbours.size()));
    regions.corner_begin.push_back(static_cast<int>(regions.corners.size()));
  }
  // The corners in affine coordinates over four vertices, which any similarity keeps.
  const auto& v = polyhedron.vertices();
  regions.basis = affineBasis(v);
  const Vec3& v0 = v[regions.basis[0]];
  Mat3 frame;
  for (int i = 0; i < 3; ++i) frame.col(i) = v[regions.basis[i + 1]] - v0;
  const Mat3 to_affine = frame.inverse();
  for (Vec3& x : regions.corners) x = to_affine * (x - v0);
  return regions;
}

const FaceRegions& LazyFaceRegions::build(const ConvexPolyhedron& owner) const {
  std::lock_guard<std::mutex> lock(buildMutex());
  if (const FaceRegions* r = ready_.load(std::memory_order_acquire)) return *r;
  value_ = std::make_shared<const FaceRegions>(computeFaceRegions(owner));
  ready_.store(value_.get(), std::memory_order_release);
  return *value_;
}

}  // namespace polydem::geometry
