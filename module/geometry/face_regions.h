// The nearest-face partition of a convex polyhedron: region k holds the points of the polyhedron
// whose nearest face plane is face k's, R_k = {x in P : d_k(x) <= d_l(x) for all l}, d the inward
// distance to a face plane. These are the sub-polyhedra of the distance potential (Zhao et al.
// section 3.1, figs. 7-9; docs/kernels/distance-potential.md): convex, one per face, meeting at the
// inner domain. The kernel needs, for each face k, the faces l whose bisector planes d_k = d_l
// bound R_k: then R_k = {d_k >= 0} intersected with {d_k <= d_l} over those l only, and a polygon
// inside P is split into regions by a handful of clips instead of one per face.
//
// The partition does not change under rigid motions or uniform scaling, so it is computed once
// per shape (on first use) and shared by its copies.
#pragma once

#include <atomic>
#include <memory>
#include <span>
#include <vector>

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
