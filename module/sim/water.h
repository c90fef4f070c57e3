// Water pressure in the joints ([water], docs/scene-format.md "Water"): on every face of a free
// block that lies on a joint plane, the hydrostatic pressure p = gamma_w (z_surface(x, y) - z)
// where it is positive, integrated exactly over the submerged part of the face
// (geometry/face_pressure.h), open joint or closed. Faces on no joint plane (the slope face, the
// region's boundary) carry none.
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
#include "polydem/particles/particle_storage.h"
#include "polydem/setup/setup.h"

namespace polydem::sim {

/// The phreatic surface at one time: z = height + slope_x (x - x0) + slope_y (y - y0).
struct PhreaticSurface {
  double x0 = 0.0, y0 = 0.0;
  double height = 0.0;  // m at (x0, y0)
  double slope_x = 0.0, slope_y = 0.0;
  double at(double x, double y) const { return height + slope_x * (x - x0) + slope_y * (y - y0); }
};

/// The surface of `water` at `time`: the table's rows interpolated linearly, the first or last
/// row held outside them.
PhreaticSurface phreaticSurface(const setup::WaterSpec& water, double time);

/// The hydrostatic pressure below `surface`, p(x) = unit_weight (z_surface(x, y) - z), written
/// about the point c.
geometry::LinearPressure hydrostaticPressure(const PhreaticSurface& surface, double unit_weight,
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
