// Face contacts split into sub-contacts at the corners of the contact area, as block DEM codes
// have done since Cundall (1988) and Hart et al. (1988) (3DEC). A single contact point carrying
// the whole normal force gives a block resting on a face no rotational stiffness while the face
// overlap does not change (the point stays put as the block tilts), so blocks rock, creep and slip
// below their friction angle (docs/dynamics.md). With a spring at every corner of the overlap, a
// tilt loads one side and unloads the other: a restoring moment, and a normal force that is the
// gradient of a potential (sum over corners of kn w g^2 / 2), so an undamped, frictionless
// contact conserves energy. Several shear springs also resist twisting about the normal.
//
// From the kernel's normal n (from B into A):
//   - A's face that faces B: among the faces around A's deepest vertex along -n, the one whose
//     outward normal is closest to -n, if within kFacingAngleDeg; B's likewise along +n.
//   - face-face: both faces are projected onto the plane normal to n and intersected; each corner
//     of the intersection is a sub-contact (a vertex of one body inside the other's face, or the
//     crossing of an edge of each), weighted by its share of the area;
//   - edge-face: one body has a facing face, the other an edge parallel to the plane (within the
//     same angle) at its deepest vertex: the edge clipped by the face gives two sub-contacts of
//     weight 1/2 (a line contact);
//   - anything else (vertex-vertex, vertex-edge, vertex-face, crossing edges) keeps the kernel's
//     single point, weight 1.
// Every sub-contact has its own gap, which may be negative (that corner is apart: no force).
// Tolerances are relative to the pair's size. Two rectangular boxes face to face take a faster
// path with the same model (face_contact_box.cpp); everything else the general one.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <span>
#include <vector>

#include "polydem/contact/contact.h"
#include "polydem/contact/face/labelled_clip.h"
#include "polydem/contact/face/square_clip.h"

namespace polydem::contact {

/// Which features of A and B a sub-contact comes from: A's feature in the high 32 bits, B's in
/// the low (labelled_clip.h). Sorting by it gives a canonical order; 0 is the single point.
using FeatureKey = std::uint64_t;

inline FeatureKey featureKey(std::uint32_t a, std::uint32_t b) {
  return (static_cast<FeatureKey>(a) << 32) | b;
}

/// The largest angle between a face's outward normal and the contact normal for the face to face
/// the other body (and between an edge and the contact plane for an edge to lie on it). Faces
/// tilted by more meet the other body with an edge or a corner. Within this angle, the corners
/// that are apart simply carry no force, so a block tipping onto an edge keeps its springs until
/// the tilt reaches this angle.
inline constexpr double kFacingAngleDeg = 20.0;
/// cos(kFacingAngleDeg): a face faces a direction when the cosine between them is larger.
inline const double kCosFacing = std::cos(kFacingAngleDeg * std::numbers::pi / 180.0);

struct SubContact {
  FeatureKey feature = 0;
  Vec3 point = Vec3::Zero();    // on the middle surface, half way between the two surfaces
  Vec3 normal = Vec3::UnitZ();  // unit, from B into A
  double gap = 0.0;             // overlap along `normal`: > 0 penetrating, <= 0 apart
  double weight = 0.0;          // share of the pair's stiffness; the weights sum to 1
};

enum class ContactArea : std::uint8_t {
  kPoint,  // one sub-contact: the kernel's point
  kLine,   // two: the ends of an edge lying on a face
  kFace,   // the corners of a face overlap
};

struct FaceContact {
  ContactArea kind = ContactArea::kPoint;
  double area = 0.0;                 // of the face overlap (kFace), m^2
  std::span<const SubContact> subs;  // sorted by feature; valid until the next build()
  int face_a = -1, face_b = -1;      // kFace: the facing faces of A and B (their shapes' indices)
};

/// Builds the sub-contacts of one contact. Keeps its buffers, so that one builder reused for every
/// pair allocates nothing once warm.
class FaceContactBuilder {
 public:
  /// `box_path`: two rectangular boxes whose faces face each other take the box-face path
  /// (face_contact_box.cpp); false sends every pair through the general path (for tests).
  explicit FaceContactBuilder(bool box_path = true) : box_path_(box_path) {}

  /// The sub-contacts of the touching contact `c` of A and B (c.normal from B into A).
  /// Each sub-contact's gap is measured along the normal of the face its vertex meets (a vertex
  /// of A inside B's face: B's face normal; a vertex of B inside A's face: minus A's), which makes
  /// the corner force the exact gradient of its spring energy; crossings of edges use c.normal.
  FaceContact build(const Body& a, const Body& b, const Contact& c);

 private:
  /// A body's face that faces the other body: its world normal and first vertex, kept from the
  /// search so that every corner on it reuses them (the same values as recomputing them).
  struct Facing {
    int face = -1;
    Vec3 normal = Vec3::Zero();
    const Vec3* base = nullptr;  // world position of the face's first vertex
  };
  /// A corner of the overlap before it becomes a sub-contact: sorted and merged by feature first,
  /// so that only the corners kept are turned into sub-contacts.
  struct Pending {
    FeatureKey feature;
    double weight;
    int corner;  // index into overlap_
  };

  static Facing facingSide(const Body& body, const Vec3& direction, int support);
  /// A box's facing face: of all its faces, the one whose normal is closest to `direction`,
  /// within the facing angle, found from the box's three axes (face_contact_box.cpp). For a
  /// rectangular box that is facingSide()'s face: a face within 20 degrees of `direction`
  /// contains the deepest vertex, and no two faces are within 40 degrees of each other, so there
  /// is no tie.
  static Facing boxFacing(const Body& body, const Vec3& direction);
  bool faceFace(const Body& a, const Body& b, const Contact& c);
  bool edgeFace(const Body& edge_body, const Body& face_body, int edge, bool edge_is_a,
                const Contact& c);
  /// The face projected onto the contact plane, counter-clockwise seen from +n; `corners` and,
  /// for a face seen from its back, `vertex` and `edge` hold the reversed lists. A facing face of
  /// A looks along -n, within the facing angle, so it is seen from its back (its projection is
  /// clockwise: its area times n_A . n < -cos 20 deg), and one of B from its front: the side is
  /// known without summing the projected area.
  LabelledPolygon project(const Body& body, int face, bool seen_from_back,
                          std::vector<Vec2>& corners, std::vector<int>& vertex,
                          std::vector<int>& edge) const;
  /// Fills `s` (every member) with the sub-contact of corner `k` of weight `weight`.
  void fromCorner(const Body& a, const Body& b, const LabelledCorner& k, const Vec3& n,
                  double weight, SubContact& s) const;
  void finish(const Body& a, const Body& b, const Vec3& n);
  /// The kind and sub-contacts of a built pair: the kernel's point where no sub-contact is
  /// penetrating while the pair is.
  FaceContact conclude(const Contact& c, ContactArea kind);
  /// Sorts pending_ by feature and merges entries of the same feature (their weights summed).
  void sortPending();
  /// The face contact of two rectangular boxes (face_contact_box.cpp): false if a body has no
  /// facing face (the general path decides then), else true with `kind` kFace or kPoint.
  bool boxFaceFace(const Body& a, const Body& b, const Contact& c, ContactArea& kind);
  /// Fills `s` with the sub-contact of box-path corner `k` of weight `weight`.
  void fromBoxCorner(const Body& a, const Body& b, const LabelledCorner& k, const Vec3& n,
                     double weight, SubContact& s) const;
  /// The point of `body`'s edge `e` that projects onto `p`. `side` is the edge's position in
  /// `polygon` (the body's projected face), whose corners are its projected ends; -1: not there.
  Vec3 lift(const Body& body, int e, int side, const LabelledPolygon& polygon, const Vec2& p) const;
  /// Coordinates of the projection of `x` onto the contact plane.
  Vec2 flat(const Vec3& x) const {
    const Vec3 d = x - frame_.origin;
    return Vec2(frame_.u.dot(d), frame_.v.dot(d));
  }

  struct Frame {
    Vec3 origin, u, v;
  } frame_;
  double scale_ = 0.0;  // the pair's length scale
  double area_ = 0.0;
  Facing facing_a_, facing_b_;
  LabelledPolygon polygon_a_, polygon_b_;  // the projected facing faces of a face-face contact
  std::vector<Vec2> corners_a_, corners_b_;
  std::vector<int> vertex_a_, vertex_b_, edge_a_, edge_b_;
  std::vector<LabelledCorner> overlap_;
  std::vector<double> shares_;
  std::vector<Pending> pending_;
  std::vector<SubContact> subs_;
  LabelledClipper clipper_;
  // The box path: A's quad and B's square, B's corners in the world (face order) and A's
  // (the quad's order), and the clip.
  bool box_path_ = true;
  LabelledQuad quad_;
  LabelledSquare square_;
  std::array<const Vec3*, 4> world_a_{}, world_b_{};
  std::array<LabelledCorner, SquareClipper::kMaxCorners> box_overlap_;
  SquareClipper square_clipper_;
};

}  // namespace polydem::contact
