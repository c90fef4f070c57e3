// FDEM potential kernel (Munjiza 2004; Zhao et al. eqs. 1-3), the distance potential's baseline.
//
// Tetrahedra of one body share their internal faces; the potential vanishes on both sides of
// such a face, so its two boundary contributions (one from each tetrahedron, opposite normals,
// the same other-body potential) cancel exactly and only faces on the body's surface are
// integrated; the internal faces still shape the potential (it is zero on them).
//
// Scratch buffers are thread_local (one thread per MPI rank); no allocation once warm.
#include "polydem/contact/potential/fdem.h"

#include <array>

#include "polydem/contact/kernel_factories.h"

namespace polydem::contact {

namespace {

// Corner loops of a tetrahedron (p0, p1, p2, p3) with positive orientation, counter-clockwise
// from outside; face k is the one opposite corner k, so face 0 is (p1, p2, p3).
constexpr std::array<int, 12> kTetLoops = {1, 2, 3, 0, 3, 2, 0, 1, 3, 0, 2, 1};

struct Tet {
  std::array<Vec3, 4> p;
  std::array<potential::CellPlane, 4> planes;
  std::array<potential::CellFace, 4> faces;
  int surface_faces = 1;  // faces[0 .. surface_faces) lie on the body's surface
  Vec3 lo, hi;

  potential::Cell cell() const {
    // No nearest-face partition: a tetrahedron's four planes all meet one another.
    return {planes, p, kTetLoops, std::span<const potential::CellFace>(faces.data(), surface_faces),
            {},     {}};
  }
};

struct FdemScratch {
  potential::OverlapIntegrator integrator;
  std::vector<Tet> tets_a, tets_b;
  std::vector<Vec3> overlap_corners;
};

FdemScratch& fdemScratch() {
  thread_local FdemScratch s;
  return s;
}

// Planes of a positively oriented tetrahedron; the potential of face k is d_k / (H_k / 4), H_k
// the height over face k (Zhao eq. 1: V_{p-face} / (4 V_{o-face}) with o its centroid, written
// as Munjiza's 4 V_i / V).
void finishTet(Tet& t, int surface_faces) {
  if ((t.p[1] - t.p[0]).cross(t.p[2] - t.p[0]).dot(t.p[3] - t.p[0]) < 0.0)
    std::swap(t.p[1], t.p[2]);
  for (int k = 0; k < 4; ++k) {
    const Vec3& x0 = t.p[kTetLoops[3 * k]];
    const Vec3& x1 = t.p[kTetLoops[3 * k + 1]];
    const Vec3& x2 = t.p[kTetLoops[3 * k + 2]];
    const Vec3 n = (x1 - x0).cross(x2 - x0).normalized();
    const double offset = n.dot(x0);
    const double height = offset - n.dot(t.p[k]);
    t.planes[k] = {n, offset, 4.0 / height};
    t.faces[k] = {k, 3 * k, 3 * k + 3};
  }
  t.surface_faces = surface_faces;
}

bool boxesOverlap(const Vec3& lo_a, const Vec3& hi_a, const Vec3& lo_b, const Vec3& hi_b) {
  return (lo_a.array() < hi_b.array()).all() && (lo_b.array() < hi_a.array()).all();
}

// The body's tetrahedra that reach into the box [lo, hi], in a frame centred on `origin`: one
// element for a tetrahedron; else one per face triangle from the centroid, polygonal faces
// fanned from their centroid (which keeps each face's symmetry). Face 0 of each tetrahedron is on
// the surface.
void buildTets(const Body& body, const Vec3& origin, const Vec3& lo, const Vec3& hi,
               std::vector<Tet>& out) {
  out.clear();
  auto corner = [&](int i) -> Vec3 { return body.vertices[i] - origin; };
  auto keep = [&](Tet& t, int surface_faces) {
    t.lo = t.p[0].cwiseMin(t.p[1]).cwiseMin(t.p[2]).cwiseMin(t.p[3]);
    t.hi = t.p[0].cwiseMax(t.p[1]).cwiseMax(t.p[2]).cwiseMax(t.p[3]);
    if (!boxesOverlap(t.lo, t.hi, lo, hi)) return;
    finishTet(t, surface_faces);
    out.push_back(t);
  };
  Tet t;
  if (body.vertices.size() == 4) {
    for (int i = 0; i < 4; ++i) t.p[i] = corner(i);
    keep(t, 4);
    return;
  }
  const Vec3 centre = body.centroid() - origin;
  for (const auto& face : body.shape->faces()) {
    const std::size_t n = face.vertices.size();
    if (n == 3) {
      t.p = {centre, corner(face.vertices[0]), corner(face.vertices[1]), corner(face.vertices[2])};
      keep(t, 1);
      continue;
    }
    const Vec3 face_centre = body.toWorld(face.centroid) - origin;
    for (std::size_t i = 0; i < n; ++i) {
      t.p = {centre, face_centre, corner(face.vertices[i]), corner(face.vertices[(i + 1) % n])};
      keep(t, 1);
    }
  }
}

}  // namespace

potential::PotentialResult FdemKernel::evaluate(const Body& a, const Body& b) const {
  potential::PotentialResult result;
  result.contact.model = ForceModel::kPotential;
  Vec3 lo, hi;
  if (!potential::commonBox(a.vertices, b.vertices, lo, hi)) return result;

  FdemScratch& s = fdemScratch();
  const Vec3 origin = 0.5 * (lo + hi);
  const Vec3 box_lo = lo - origin, box_hi = hi - origin;
  buildTets(a, origin, box_lo, box_hi, s.tets_a);
  buildTets(b, origin, box_lo, box_hi, s.tets_b);

  potential::OverlapSums sums;
  s.overlap_corners.clear();
  bool found = false;
  for (const Tet& ta : s.tets_a) {
    for (const Tet& tb : s.tets_b) {
      if (!boxesOverlap(ta.lo, ta.hi, tb.lo, tb.hi)) continue;
      const Vec3 pair_lo = ta.lo.cwiseMax(tb.lo).cwiseMax(box_lo);
      const Vec3 pair_hi = ta.hi.cwiseMin(tb.hi).cwiseMin(box_hi);
      found =
          s.integrator.add(ta.cell(), tb.cell(), pair_lo, pair_hi, sums, s.overlap_corners).found ||
          found;
    }
  }
  if (!found) return result;
  const Vec3 apart = a.centroid() - b.centroid();
  const Vec3 fallback = apart.squaredNorm() > 0.0 ? Vec3(apart.normalized()) : Vec3(Vec3::UnitZ());
  return potential::finishContact(sums, s.overlap_corners, origin,
                                  a.circumradius() + b.circumradius(), fallback);
}

Contact FdemKernel::collide(const Body& a, const Body& b, particles::PairState*) const {
  return evaluate(a, b).contact;
}

std::unique_ptr<Kernel> makeFdemKernel(const KernelParams&) {
  return std::make_unique<FdemKernel>();
}

}  // namespace polydem::contact
