// A reference sub-contact builder: the straightforward general algorithm (face_contact.cpp,
// labelled_clip.cpp at commit 52dd9b9, without the library's shortcuts), kept verbatim for tests
// only: the library's builder must give the same sub-contacts up to round-off
// (face_contact_reference_test.cpp). Not maintained beyond that comparison: the library's
// documentation is the model's.
#pragma once

#include <vector>

#include "polydem/contact/face/face_contact.h"

namespace polydem::contact::reference {

class ReferenceClipper {
 public:
  /// The intersection of A's polygon with B's (both convex, counter-clockwise), corners
  /// counter-clockwise. A corner of A inside B is labelled (vertex of A, face of B); a corner of B
  /// inside A (face of A, vertex of B); a crossing (edge of A, edge of B). Empty if they do not
  /// overlap. Corners closer than `merge` to the previous one are dropped (degenerate touching).
  void polygons(const LabelledPolygon& a, const LabelledPolygon& b, double merge,
                std::vector<LabelledCorner>& out);

  /// The part of a segment inside a convex counter-clockwise polygon: 0 or 2 corners. The segment
  /// belongs to `segment_is_a` ? A : B, runs from `s0` (vertex `v0`) to `s1` (vertex `v1`) along
  /// edge `edge`; the polygon is the other body's face. An end inside the polygon is labelled
  /// (vertex, face); an end cut by the polygon's edge k is a crossing (edge, edge k).
  void segment(const Vec2& s0, const Vec2& s1, int v0, int v1, int edge, bool segment_is_a,
               const LabelledPolygon& polygon, std::vector<LabelledCorner>& out);

 private:
  struct Working {
    LabelledCorner corner;
    std::int32_t carrier;  // the edge leaving this corner: >= 0 an edge of A, < 0 clip line -1-k
  };
  std::vector<Working> poly_, next_;
  std::vector<double> h_;
};

class ReferenceFaceContactBuilder {
 public:
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
  bool faceFace(const Body& a, const Body& b, const Contact& c);
  bool edgeFace(const Body& edge_body, const Body& face_body, int edge, bool edge_is_a,
                const Contact& c);
  /// The face projected onto the contact plane, counter-clockwise seen from +n; `corners` and,
  /// for a face seen from its back, `vertex` and `edge` hold the reversed lists.
  LabelledPolygon project(const Body& body, int face, std::vector<Vec2>& corners,
                          std::vector<int>& vertex, std::vector<int>& edge) const;
  /// Fills `s` (every member) with the sub-contact of corner `k` of weight `weight`.
  void fromCorner(const Body& a, const Body& b, const LabelledCorner& k, const Vec3& n,
                  double weight, SubContact& s) const;
  void finish(const Body& a, const Body& b, const Vec3& n);

  struct Frame {
    Vec3 origin, u, v;
  } frame_;
  double scale_ = 0.0;  // the pair's length scale
  double area_ = 0.0;
  Facing facing_a_, facing_b_;
  std::vector<Vec2> corners_a_, corners_b_;
  std::vector<int> vertex_a_, vertex_b_, edge_a_, edge_b_;
  std::vector<LabelledCorner> overlap_;
  std::vector<double> shares_;
  std::vector<Pending> pending_;
  std::vector<SubContact> subs_;
  ReferenceClipper clipper_;
};

}  // namespace polydem::contact::reference
