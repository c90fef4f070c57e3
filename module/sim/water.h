// Water pressure in the joints ([water], docs/scene-format.md "Water"): on every face of a free
// block that lies on a joint plane, the hydrostatic pressure p = gamma_w (z_surface(x, y) - z)
// where it is positive, integrated exactly over the submerged part of the face
// (geometry/face_pressure.h), open joint or closed. Faces on no joint plane (the slope face, the
// region's boundary) carry none. The surface is a level, the plane through three points, or a
// surface through more points, linear on each triangle of their triangulation in plan and
// continued beyond their hull at the height of its nearest point (geometry/plan_partition.h);
// a [[water.joint]] gives the faces of its planes a surface of their own, or none (dry).
//
// The water force is applied to the blocks as a load, next to gravity, so the contact forces the
// joint law computes are the effective ones: the law sees the effective normal stress
// sigma' = sigma - u (Terzaghi) without being told the pore pressure u.
//
// A block's water force depends only on that block's pose and the time, so the forces are the
// same bits on any number of ranks.
#pragma once

#include <span>
#include <vector>

#include "polydem/dynamics/monitors.h"
#include "polydem/geometry/face_pressure.h"
#include "polydem/geometry/plan_partition.h"
#include "polydem/particles/particle_storage.h"
#include "polydem/setup/setup.h"

namespace polydem::sim {

/// The level or three-point surface of `water` at `time`: the table's rows interpolated
/// linearly, the first or last row held outside them.
geometry::PlanPlane phreaticSurface(const setup::WaterSurfaceSpec& water, double time);

/// The heights of the surface's points (or its level) at `time`, as phreaticSurface, into `z`.
void surfaceHeights(const setup::WaterSurfaceSpec& water, double time, std::vector<double>& z);

/// The resultant of the water pressure of `surface` at `time` on one face: the polygon
/// vertices[face[k]] with outward `normal`, moments about `c`; zero for a dry surface. What
/// addWaterForces applies, for a caller that wants one face.
geometry::PressureResultant waterOnFace(const setup::WaterSurfaceSpec& surface, double unit_weight,
                                        double time, std::span<const Vec3> vertices,
                                        std::span<const int> face, const Vec3& normal,
                                        const Vec3& c);

/// The hydrostatic pressure below `surface`, p(x) = unit_weight (z_surface(x, y) - z), written
/// about the point c.
geometry::LinearPressure hydrostaticPressure(const geometry::PlanPlane& surface, double unit_weight,
                                             const Vec3& c);

/// The mean water pressure on each face of a free block (Pa) into `out` (one per face): the
/// pressure integrated over the wetted part of the face divided by the face's area, so the
/// hydrostatic value at the face's centroid for a face wholly below the surface; 0 on faces on no
/// joint plane and on dry faces. `vertices`, `normals`: the block's world vertices and face
/// normals; `centroid`: its centroid. What the snapshots show (field `pressure`).
void faceWaterPressures(const setup::WaterSpec& water, double time,
                        const geometry::BodyShape& shape, std::span<const Vec3> vertices,
                        std::span<const Vec3> normals, const Vec3& centroid,
                        std::vector<double>& out);

/// Adds the water force and its moment about the centroid on every joint face of this rank's
/// free particles (entries [0, forces.size()) of `particles`, whose derived data is current).
void addWaterForces(const setup::WaterSpec& water, double time, const particles::ShapeTable& shapes,
                    const particles::ParticleStorage& particles,
                    std::span<dynamics::ForceAccumulator> forces);

}  // namespace polydem::sim
