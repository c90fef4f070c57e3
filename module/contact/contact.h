// The narrow phase: one result type and one interface for every contact kernel.
//
// Conventions (BENCHMARKS.md section C): the pair is (A, B); `normal` is the unit vector pointing
// from B into A, the direction in which A must move to separate; `depth` >= 0 is the penetration;
// `point` is the single contact point, in the middle of the overlap (half way between the two
// surfaces). Kernels are stateless functors: all per-pair memory (warm starts, previous planes)
// lives in a PairState (particles/pair_state.h) owned by the contact history, so that it can
// migrate with particles and be written to checkpoints.
#pragma once

#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "polydem/core/types.h"
#include "polydem/geometry/convex_polyhedron.h"
#include "polydem/particles/pair_state.h"

namespace polydem::contact {

/// A polyhedron placed in the world: world = position + rotation * (shape vertex).
/// `vertices` holds the world coordinates of the shape's vertices in the shape's order; the
/// simulation computes them once per particle per step and every pair reuses them.
/// `face_normals`, if not empty, holds rotation * (shape face normal) for every face in the
/// shape's order, computed once per particle per step by the simulation (the same products as
/// faceNormal() computes on demand, so the same bits); a pair of a dense pack asks for each
/// face's normal several times (separating axes, facing faces).
struct Body {
  const geometry::ConvexPolyhedron* shape = nullptr;
  Vec3 position = Vec3::Zero();
  Mat3 rotation = Mat3::Identity();
  std::span<const Vec3> vertices;
  std::span<const Vec3> face_normals = {};

  Vec3 toWorld(const Vec3& body) const { return position + rotation * body; }
  Vec3 centroid() const { return toWorld(shape->centroid()); }
  Vec3 faceNormal(int f) const {
    return face_normals.empty() ? Vec3(rotation * shape->faces()[f].normal) : face_normals[f];
  }
  double circumradius() const { return shape->circumradius(); }
};

/// Builds a Body whose world vertices live in `storage` (kept alive by the caller).
Body placeBody(const geometry::ConvexPolyhedron& shape, const Vec3& position, const Mat3& rotation,
               std::vector<Vec3>& storage);

/// How the force of a contact is to be computed by the contact law.
enum class ForceModel : std::uint8_t {
  kPenalty,    // f_n = kn * depth along `normal`, acting at `point`
  kPotential,  // f_n = penalty (Pa) * `potential` (m^2) along `normal`, acting at `point`
};

/// Why a kernel could not give a trustworthy answer (the contact is still reported).
enum class Status : std::uint8_t {
  kOk = 0,
  kNotConverged,       // an iteration hit its bound; the best answer so far is returned
  kDegenerate,         // no overlap polygon/volume could be formed; point falls back
  kInnerDomainReached  // distance potential: the overlap reached the undefined inner domain
};

struct Contact {
  bool touching = false;
  Vec3 normal = Vec3::UnitZ();
  Vec3 point = Vec3::Zero();
  double depth = 0.0;
  ForceModel model = ForceModel::kPenalty;
  double potential = 0.0;  // kPotential only: integral of the potential over the overlap surface
  Status status = Status::kOk;
};

class Kernel {
 public:
  virtual ~Kernel() = default;
  virtual std::string_view name() const = 0;
  /// Resolves the pair (a, b). `state` may be null (no warm start, nothing remembered).
  virtual Contact collide(const Body& a, const Body& b, particles::PairState* state) const = 0;
  /// The same for a caller that replaces the point of face and edge contacts by sub-contacts
  /// (contact/face/face_contact.h): a kernel may skip work that only places the point on such
  /// contacts (the IPM kernels return their base kernel's answer, whose point is right for the
  /// contacts that keep one point: a vertex on a face, crossing edges). Normal and depth are
  /// collide()'s.
  virtual Contact collideForSubContacts(const Body& a, const Body& b,
                                        particles::PairState* state) const {
    return collide(a, b, state);
  }
};

/// Parameters some kernels take; every kernel ignores the ones it does not use.
struct KernelParams {
  double lp_rounding = 0.05;  // LP potential blocks: rounding radius r, fraction of inradius
  // gjk-epa, gjk-epa-ipm: the exact separating-axis test for small shapes (contact/sat/sat.h);
  // false keeps GJK + EPA for every pair (e.g. to continue, to the same bits, a run written by a
  // polydem without the separating-axis test).
  bool separating_axes = true;
};

/// The kernel called `name` (gjk-epa, gjk-epa-ipm, fcp, fcp-ipm, lp, distance-potential, fdem).
/// Throws polydem::Error listing the known names for an unknown one.
std::unique_ptr<Kernel> makeKernel(std::string_view name, const KernelParams& params = {});
/// The names makeKernel() accepts, in the order reports list them.
std::vector<std::string> kernelNames();

}  // namespace polydem::contact
