// The nearest-face partition of a convex polyhedron: region k holds the points of the polyhedron
// whose nearest face plane is face k's, R_k = {x in P : d_k(x) <= d_l(x) for all l}, d the inward
// distance to a face plane. These are the sub-polyhedra of the distance potential (Zhao et al.
// section 3.1, figs. 7-9; docs/kernels/distance-potential.md): convex, one per face, meeting at the
// inner domain. The kernel needs, for each face k, the faces l whose bisector planes d_k = d_l
// bound R_k: then R_k = {d_k >= 0} intersected with {d_k <= d_l} over those l only, and a polygon
// inside P is split into regions by a handful of clips instead of one per face.
//
// Each region is also kept as its corners and, per neighbour, the corners on their shared facet:
// a plane that meets no point of the facet of k and l cannot be where a polygon in that plane
// leaves region k for region l, and the kernel skips l's clip there.
//
// The partition does not change under rigid motions or uniform scaling (nor do affine
// coordinates), so it is computed once per shape (on first use) and shared by its copies.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "polydem/core/types.h"

namespace polydem::geometry {

class ConvexPolyhedron;

/// For each face k, the faces whose bisector plane with k comes within round-off (1e-9 of the
/// length scale) of region k: every face bounding R_k in a facet, and possibly a few that only
/// touch it at a corner or an edge (a superset is exact, only slower; missing one would not be).
struct FaceRegions {
  std::vector<int> begin;       // neighbours of face k: neighbours[begin[k] .. begin[k + 1])
  std::vector<int> neighbours;  // ascending per face
  std::span<const int> of(int k) const {
    return std::span<const int>(neighbours).subspan(begin[k], begin[k + 1] - begin[k]);
  }

  // Where the regions lie, in affine coordinates (a, b, c) over four vertices of the shape:
  // x = v0 + a (v1 - v0) + b (v2 - v0) + c (v3 - v0), vi = vertices[basis[i]]. They hold in any
  // frame the shape is moved or scaled to, so copies can share them.
  std::array<int, 4> basis{};
  std::vector<int> corner_begin;  // corners of region k: corners[corner_begin[k] .. [k + 1])
  std::vector<Vec3> corners;      // affine coordinates, no two within 1e-10 of the length scale
  /// Parallel to `neighbours`: bit i set when corner i of region k lies (within 1e-9 of the
  /// length scale) on the bisector with that neighbour, so that the facet the two regions share
  /// lies in the corners' convex hull. Only for regions of at most kMaskedCorners corners; the
  /// others have every bit set (no facet is ever skipped there).
  std::vector<std::uint64_t> facets;
  static constexpr int kMaskedCorners = 64;
};

/// Builds each region by clipping the polyhedron by the bisector half-spaces (O(faces^2) clips
/// of a small polytope; about a millisecond for 76 faces).
FaceRegions computeFaceRegions(const ConvexPolyhedron& polyhedron);

/// A FaceRegions computed on first use and kept. Copies share the computed value; the first use
/// is guarded, so shapes shared by threads stay safe; later uses are one atomic load.
class LazyFaceRegions {
 public:
  LazyFaceRegions() = default;
  LazyFaceRegions(const LazyFaceRegions& other) { copyFrom(other); }
  LazyFaceRegions(LazyFaceRegions&& other) noexcept { copyFrom(other); }
  LazyFaceRegions& operator=(const LazyFaceRegions& other) {
    copyFrom(other);
    return *this;
  }
  LazyFaceRegions& operator=(LazyFaceRegions&& other) noexcept {
    copyFrom(other);
    return *this;
  }

  const FaceRegions& get(const ConvexPolyhedron& owner) const {
    if (const FaceRegions* r = ready_.load(std::memory_order_acquire)) return *r;
    return build(owner);
  }

 private:
  // Once ready_ is set, value_ never changes again, so a copy may read it without a lock.
  void copyFrom(const LazyFaceRegions& other) noexcept {
    const FaceRegions* r = other.ready_.load(std::memory_order_acquire);
    value_ = r != nullptr ? other.value_ : nullptr;
    ready_.store(r, std::memory_order_release);
  }
  const FaceRegions& build(const ConvexPolyhedron& owner) const;

  mutable std::shared_ptr<const FaceRegions> value_;
  mutable std::atomic<const FaceRegions*> ready_{nullptr};
};

}  // namespace polydem::geometry
