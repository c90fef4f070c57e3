// The blocks a bolt crosses and its crossing points (bolt_geometry.h).
#include "polydem/sim/bolt_geometry.h"

#include <algorithm>
#include <cmath>

#include "polydem/core/error.h"
#include "polydem/core/strings.h"

namespace polydem::sim {

namespace {

// The part [t0, t1] of the segment p + t (q - p), t in [0, 1], inside the convex body (its faces'
// half-spaces, body frame); empty when t0 >= t1.
struct Interval {
  double t0 = 0.0, t1 = 1.0;
  std::size_t particle = 0;
};

Interval clipSegment(const geometry::ConvexPolyhedron& hull, const Vec3& p, const Vec3& q) {
  Interval in;
  const Vec3 d = q - p;
  for (const auto& f : hull.faces()) {
    const double start = f.normal.dot(p) - f.offset;  // > 0: outside
    const double rate = f.normal.dot(d);
    if (rate == 0.0) {
      if (start > 0.0) return {1.0, 0.0};
      continue;
    }
    const double t = -start / rate;
    if (rate > 0.0) {
      in.t1 = std::min(in.t1, t);
    } else {
      in.t0 = std::max(in.t0, t);
    }
  }
  return in;
}

[[noreturn]] void refuse(const setup::Setup& scene, const setup::BoltSpec& bolt,
                         const std::string& why) {
  throw InputError(scene.file, bolt.line, cat("[[bolt]] '", bolt.name, "': ", why));
}

}  // namespace

std::vector<BoltCrossing> boltCrossings(const setup::Setup& scene, const setup::BoltSpec& bolt,
                                        const std::function<InitialBody(std::size_t)>& body) {
  const Vec3 start = bolt.start, end = bolt.start + bolt.length * bolt.direction;
  // A block counts when the bolt runs through it over more than this share of its length (a
  // segment that only grazes an edge or a face anchors nothing).
  const double min_share = 1e-9;
  std::vector<Interval> pieces;
  for (std::size_t i = 0; i < scene.particles.size(); ++i) {
    const InitialBody b = body(i);
    // The bounding sphere first: most blocks of a rock mass are far from the bolt.
    const double s = std::clamp((b.centroid - start).dot(bolt.direction), 0.0, bolt.length);
    if ((start + s * bolt.direction - b.centroid).norm() > b.shape->circumradius) continue;
    const Mat3 to_body = b.orientation.toRotationMatrix().transpose();
    Interval in = clipSegment(*b.shape->polyhedron, to_body * (start - b.centroid),
                              to_body * (end - b.centroid));
    if (in.t1 - in.t0 <= min_share) continue;
    in.particle = i;
    pieces.push_back(in);
  }
  if (pieces.size() < 2) {
    refuse(scene, bolt,
           pieces.empty() ? "its segment lies in no block"
                          : cat("its segment lies in one block only (particle ",
                                scene.particles[pieces[0].particle].uid,
                                "): it crosses no joint; lengthen it or move its start"));
  }
  std::sort(pieces.begin(), pieces.end(), [](const Interval& x, const Interval& y) {
    return x.t0 != y.t0 ? x.t0 < y.t0 : x.particle < y.particle;
  });
  std::vector<BoltCrossing> crossings;
  for (std::size_t k = 0; k + 1 < pieces.size(); ++k) {
    const Interval &pa = pieces[k], &pb = pieces[k + 1];
    const InitialBody a = body(pa.particle), b = body(pb.particle);
    if (!a.free && !b.free) continue;  // nothing moves at a joint between fixed bodies
    // The joint lies between the end of one piece and the start of the next (the middle of an
    // open joint's gap, or of an overlap).
    const double t = 0.5 * (pa.t1 + pb.t0);
    const auto at = [&](double u) { return start + (u * bolt.length) * bolt.direction; };
    const Mat3 ra = a.orientation.toRotationMatrix().transpose();
    const Mat3 rb = b.orientation.toRotationMatrix().transpose();
    BoltCrossing c;
    c.a = scene.particles[pa.particle].uid;
    c.b = scene.particles[pb.particle].uid;
    c.point = at(t);
    c.anchor_a = ra * (c.point - a.centroid);
    c.anchor_b = rb * (c.point - b.centroid);
    c.axis_a = ra * bolt.direction;
    c.middle_a = ra * (at(0.5 * (pa.t0 + pa.t1)) - a.centroid);
    c.middle_b = rb * (at(0.5 * (pb.t0 + pb.t1)) - b.centroid);
    crossings.push_back(c);
  }
  if (crossings.empty()) {
    refuse(scene, bolt, "it crosses only joints between fixed bodies: it holds no free block");
  }
  return crossings;
}

}  // namespace polydem::sim
