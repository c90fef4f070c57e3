// The frame of a rectangular box (a parallelepiped whose edges are orthogonal within round-off),
// found once per shape (ConvexPolyhedron::box()) so that the separating-axis test of two boxes
// can take its 15 axes from the two rotations (contact/sat/sat_obb.cpp) instead of their vertices.
#pragma once

#include <array>
#include <optional>

#include "polydem/core/types.h"

namespace polydem::geometry {

class ConvexPolyhedron;

struct BoxFrame {
  /// A polyhedron is a box when `skew` is at most this: its error in the closed-form
  /// projection c . u -+ sum_k h_k |a_k . u| is then below 1e-14 of the box's size, far below
  /// the 1e-12 that contact tolerances allow.
  static constexpr double kMaxSkew = 1e-14;

  Vec3 centre;               // the mean of the corners, in the polyhedron's frame
  std::array<Vec3, 3> axis;  // a_k: the unit normal of faces()[axisFaces()[k]]
  Vec3 half;                 // h_k: half the side along a_k
  /// axisEdges()[i] runs along edge_sign[i] * axis[edge_axis[i]].
  std::array<int, 3> edge_axis;
  std::array<double, 3> edge_sign;
  /// The vertex at centre + sum_k s_k h_k a_k, with s_k = +1 where bit k of the index is set.
  std::array<int, 8> corner;
  /// The face whose outward normal is +a_k (face[2k]) or -a_k (face[2k + 1]): a box's facing
  /// face is found from its three axes instead of a search over its faces.
  std::array<int, 6> face;
  /// The largest of |a_i . a_j| (i != j), |e x a| over the unit axis edges e and their axes, and
  /// | |(v - centre) . a_k| - h_k | / max h over the corners v: how far from a rectangular box.
  double skew = 0.0;
};

/// The box frame of `p`, or nothing if `p` is not a rectangular box within BoxFrame::kMaxSkew.
std::optional<BoxFrame> findBoxFrame(const ConvexPolyhedron& p);

}  // namespace polydem::geometry
