// The cells of the potential kernels (distance-potential: one per body; fdem: one per
// tetrahedron): convex, bounded by planes, each plane carrying a linear term of the cell's
// potential phi = min over the planes of the terms (docs/kernels/distance-potential.md).
#pragma once

#include <array>
#include <cstdint>
#include <span>

#include "polydem/core/types.h"
#include "polydem/geometry/face_regions.h"

namespace polydem::contact::potential {

/// A face plane of a cell: inside is normal.x <= offset; its term of the potential is
/// (offset - normal.x) * inv_scale (dimensionless).
struct CellPlane {
  Vec3 normal = Vec3::UnitZ();
  double offset = 0.0;
  double inv_scale = 0.0;
  double term(const Vec3& x) const { return (offset - normal.dot(x)) * inv_scale; }
};

/// A face to integrate over: plane `plane`, corners loops[begin .. end) counter-clockwise seen
/// from outside.
struct CellFace {
  int plane = 0;
  int begin = 0, end = 0;
};

/// Where a cell's regions lie (optional, geometry::FaceRegions): region k's corners in affine
/// coordinates over four of the cell's corners, and per neighbour (parallel to
/// Cell::region_neighbours) the mask of region k's corners on their shared facet.
struct RegionFacets {
  std::span<const int> corner_begin;  // empty: no region is located
  std::span<const Vec3> corners;
  std::span<const std::uint64_t> masks;
  std::array<int, 4> basis{};  // indices into Cell::corners
  double tolerance = 0.0;      // how far from a plane a point still counts as on it (m)
  // Larger regions have every facet bit set (never skipped) and are not tested corner by corner.
  static constexpr int kMaskedCorners = geometry::FaceRegions::kMaskedCorners;
};

/// A convex cell. `planes` are all its planes (they bound it and define its potential); `faces`
/// are the faces on the body's surface: faces shared by two cells of one body (FDEM's internal
/// tetrahedron faces) are left out, since their two contributions cancel exactly.
/// `region_begin` / `region_neighbours` (optional, geometry::FaceRegions): for each plane k, the
/// planes whose bisectors bound k's region {phi = term_k}; empty: every other plane may.
struct Cell {
  std::span<const CellPlane> planes;
  std::span<const Vec3> corners;
  std::span<const int> loops;
  std::span<const CellFace> faces;
  std::span<const int> region_begin;
  std::span<const int> region_neighbours;
  // A default, so that cells built without it (FDEM's) need not name it.
  RegionFacets facets = {};
};

}  // namespace polydem::contact::potential
