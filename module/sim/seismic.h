// The pseudo-static earthquake load ([seismic], docs/scene-format.md "Earthquakes"): the
// pseudo-static method of slope stability (Terzaghi 1950; Hoek and Bray, Rock Slope Engineering,
// ch. 6) replaces the earthquake by a constant body force on every free block,
// m g (kh h + kv z): kh g horizontal in the direction h of the azimuth, kv g vertical (positive
// upward). It is added next to gravity, in the same fixed order, so it is the same bits on any
// rank count.
#pragma once

#include "polydem/core/types.h"
#include "polydem/setup/setup.h"

namespace polydem::sim {

/// The seismic acceleration g (kh h + kv z), g = |gravity|, h = (sin azimuth, cos azimuth, 0).
Vec3 seismicAcceleration(const setup::SeismicSpec& seismic, const Vec3& gravity);

/// What every free block is accelerated by before its contacts: gravity, plus the seismic
/// acceleration when the scene has [seismic] (gravity itself, bit for bit, without).
Vec3 bodyAcceleration(const setup::Setup& scene);

}  // namespace polydem::sim
