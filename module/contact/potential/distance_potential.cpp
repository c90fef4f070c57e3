// Distance-potential kernel (Zhao et al., sections 3.1-3.2).
//
// phi is Zhao eq. 5 on the sub-polyhedra of figs. 7-9: phi = h / r in the sub-polyhedron of face
// i, h the distance to face i. The sub-polyhedron of face i is the region swept by face i when all
// faces move inward at equal speed (fig. 8: boundaries at equal distance from the bases), which is
// exactly where face i is the nearest face plane; so phi(x) = min_i d_i(x) / r, one cell per body
// with every plane scaled by r (docs/kernels/distance-potential.md gives the proof).
//
// Scratch buffers are thread_local: polydem runs one thread per MPI rank, and a kernel object may
// be shared; once they have grown to the largest pair seen, collide() allocates nothing.
#include "polydem/contact/potential/distance_potential.h"

#include <algorithm>

#include "polydem/contact/kernel_factories.h"
#include "polydem/geometry/small_lp.h"

namespace polydem::contact {

namespace {

struct CellBuffers {
  std::vector<potential::CellPlane> planes;
  std::vector<Vec3> corners;
  std::vector<int> loops;
  std::vector<potential::CellFace> faces;

  std::span<const int> region_begin, region_neighbours;
  potential::RegionFacets facets;

  potential::Cell cell() const {
    return {planes, corners, loops, faces, region_begin, region_neighbours, facets};
  }
};

struct DistanceScratch {
  potential::OverlapIntegrator integrator;
  CellBuffers a, b;
  std::vector<Vec3> overlap_corners;
  std::vector<geometry::Vec4> rows;
  std::vector<double> rhs;
};

DistanceScratch& distanceScratch() {
  thread_local DistanceScratch s;
  return s;
}

// One cell for the whole body, in a frame centred on `origin`; every plane scaled by 1/r.
void buildCell(const Body& body, const Vec3& origin, CellBuffers& out) {
  const auto& faces = body.shape->faces();
  const double inv_r = 1.0 / body.shape->inradius();
  const Vec3 shift = body.position - origin;
  out.planes.resize(faces.size());
  out.faces.resize(faces.size());
  out.loops.clear();
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const Vec3 n = body.rotation * faces[f].normal;
    out.planes[f] = {n, faces[f].offset + n.dot(shift), inv_r};
    out.faces[f].plane = static_cast<int>(f);
    out.faces[f].begin = static_cast<int>(out.loops.size());
    out.loops.insert(out.loops.end(), faces[f].vertices.begin(), faces[f].vertices.end());
    out.faces[f].end = static_cast<int>(out.loops.size());
  }
  // One plane per face, in face order: the shape's nearest-face partition applies as it is.
  const geometry::FaceRegions& regions = body.shape->faceRegions();
  out.region_begin = regions.begin;
  out.region_neighbours = regions.neighbours;
  // Where the regions lie: their corners in affine coordinates over four of the body's vertices
  // (out.corners), and the tolerance of the facet test, far above the round-off of both.
  out.facets = {regions.corner_begin, regions.corners, regions.facets, regions.basis,
                1e-9 * body.shape->lengthScale()};
  out.corners.resize(body.vertices.size());
  for (std::size_t i = 0; i < body.vertices.size(); ++i) out.corners[i] = body.vertices[i] - origin;
}

// Whether the point x (in the cells' frame) is at least r (1 - 1e-12) from every plane of `own`
// and lies inside every plane of `other` by 1e-9 of the bodies' size: then (x, t = r) is a
// feasible point of innerDomainReached's LP, whose optimum is at least that.
bool innerPointInside(const potential::Cell& own, double inradius, const potential::Cell& other,
                      const Vec3& x, double size) {
  for (const auto& p : own.planes) {
    if (p.offset - p.normal.dot(x) < inradius * (1.0 - 1e-12)) return false;
  }
  for (const auto& p : other.planes) {
    if (p.normal.dot(x) - p.offset > -1e-9 * size) return false;
  }
  return true;
}

// Whether the overlap contains a point of `own`'s inner domain (distance >= r from all its faces):
// maximise t subject to x in `other` and d_i(x) >= t for own's planes (a 4-unknown LP). The
// shape's in-centre `incentre` (in the cells' frame) is such a point; when it lies inside `other`
// the answer is yes without the LP (the LP's optimum is t = r there: the same answer).
bool innerDomainReached(const potential::Cell& own, double inradius, const Vec3& incentre,
                        const potential::Cell& other, double size, DistanceScratch& s) {
  if (innerPointInside(own, inradius, other, incentre, size)) return true;
  s.rows.clear();
  s.rhs.clear();
  for (const auto& p : other.planes) {
    s.rows.emplace_back(p.normal.x(), p.normal.y(), p.normal.z(), 0.0);
    s.rhs.push_back(p.offset);
  }
  for (const auto& p : own.planes) {
    s.rows.emplace_back(p.normal.x(), p.normal.y(), p.normal.z(), 1.0);
    s.rhs.push_back(p.offset);
  }
  const auto lp = geometry::solveSmallLp(s.rows, s.rhs, geometry::Vec4(0, 0, 0, -1));
  return lp.status == geometry::SmallLpResult::Status::kOptimal &&
         lp.z[3] >= inradius * (1.0 - 1e-9);
}

}  // namespace

potential::PotentialResult DistancePotentialKernel::evaluate(const Body& a, const Body& b) const {
  potential::PotentialResult result;
  result.contact.model = ForceModel::kPotential;
  Vec3 lo, hi;
  if (!potential::commonBox(a.vertices, b.vertices, lo, hi)) return result;

  DistanceScratch& s = distanceScratch();
  const Vec3 origin = 0.5 * (lo + hi);
  buildCell(a, origin, s.a);
  buildCell(b, origin, s.b);
  const potential::Cell cell_a = s.a.cell(), cell_b = s.b.cell();
  potential::OverlapSums sums;
  s.overlap_corners.clear();
  const potential::PairInfo info =
      s.integrator.add(cell_a, cell_b, lo - origin, hi - origin, sums, s.overlap_corners);
  if (!info.found) return result;

  const Vec3 apart = a.centroid() - b.centroid();
  const Vec3 fallback = apart.squaredNorm() > 0.0 ? Vec3(apart.normalized()) : Vec3(Vec3::UnitZ());
  result = potential::finishContact(sums, s.overlap_corners, origin,
                                    a.circumradius() + b.circumradius(), fallback);
  result.bound_a = info.bound_a;
  result.bound_b = info.bound_b;
  // A vanishing force (kDegenerate) says more than the inner domain: keep it.
  if (!result.contact.touching || result.contact.status != Status::kOk) return result;
  // phi <= bound < 1 on the overlap proves the inner domain is not reached; otherwise ask the LP.
  constexpr double kNearOne = 1.0 - 1e-9;
  const double size = a.circumradius() + b.circumradius();
  const bool reached =
      (info.bound_a >= kNearOne &&
       innerDomainReached(cell_a, a.shape->inradius(), a.toWorld(a.shape->incenter()) - origin,
                          cell_b, size, s)) ||
      (info.bound_b >= kNearOne &&
       innerDomainReached(cell_b, b.shape->inradius(), b.toWorld(b.shape->incenter()) - origin,
                          cell_a, size, s));
  if (reached) result.contact.status = Status::kInnerDomainReached;
  return result;
}

Contact DistancePotentialKernel::collide(const Body& a, const Body& b,
                                         particles::PairState*) const {
  return evaluate(a, b).contact;
}

std::unique_ptr<Kernel> makeDistancePotentialKernel(const KernelParams&) {
  return std::make_unique<DistancePotentialKernel>();
}

}  // namespace polydem::contact
