// The datasets of a checkpoint file, their units and descriptions: one table that the writer,
// the reader and docs/checkpoint.md follow (internal to checkpoint).
#pragma once

#include <cstddef>
#include <cstdint>

namespace polydem::checkpoint::layout {

struct Dataset {
  const char* name;
  const char* units;  // "" for counts, indices, flags and text
  const char* description;
};

inline constexpr const char* kFormatName = "polydem-checkpoint";
inline constexpr const char* kDigestAlgorithm =
    "polydem-sum64 over the bytes of a walk of every group, dataset, link and attribute of the "
    "file (the root's digest attribute left out), docs/checkpoint.md";
inline constexpr const char* kChecksumAlgorithm =
    "polydem-sum64: mix64((sum_j mix64(u_j + (j+1)*0x9e3779b97f4a7c15)) xor E) over the E "
    "elements u_j in row-major order, mix64 = SplitMix64 finaliser (docs/checkpoint.md)";

// --- /run and /scene
// ------------------------------------------------------------------------------
inline constexpr Dataset kRunState{"/run/state", "",
                                   "opaque run state (JSON) of checks and tracker"};
inline constexpr Dataset kSceneToml{"/scene/toml", "", "the scene file, verbatim"};

// --- /shapes: body frame, mass properties per unit density
// -----------------------------------------
inline constexpr Dataset kShapeName{"/shapes/name", "", "shape names"};
inline constexpr Dataset kShapeVertexOffset{
    "/shapes/vertex_offset", "",
    "shape s has rows vertex_offset[s] .. vertex_offset[s+1]-1 of vertices"};
inline constexpr Dataset kShapeVertices{"/shapes/vertices", "m", "vertices in the body frame"};
inline constexpr Dataset kShapeFaceOffset{"/shapes/face_offset", "",
                                          "shape s has faces face_offset[s] .. face_offset[s+1]-1"};
inline constexpr Dataset kFaceVertexOffset{
    "/shapes/face_vertex_offset", "",
    "face f has entries face_vertex_offset[f] .. face_vertex_offset[f+1]-1 of face_vertices"};
inline constexpr Dataset kFaceVertices{
    "/shapes/face_vertices", "",
    "vertex indices (within the shape), counter-clockwise seen from outside"};
inline constexpr Dataset kShapeVolume{"/shapes/volume", "m^3", "volume"};
inline constexpr Dataset kShapeMoments{
    "/shapes/principal_moments", "m^5",
    "principal moments of inertia per unit density (times density: kg m^2)"};
inline constexpr Dataset kShapeCircumradius{"/shapes/circumradius", "m",
                                            "largest centroid-vertex distance"};
inline constexpr Dataset kShapeInradius{"/shapes/inradius", "m", "largest inscribed sphere radius"};
inline constexpr Dataset kShapeFacePlane{
    "/shapes/face_plane", "",
    "per face (rows as /shapes/face_vertex_offset): the scene's joint plane it lies on, -1: none"};

// --- /materials
// -----------------------------------------------------------------------------------
inline constexpr Dataset kMaterialName{"/materials/name", "", "material names"};
inline constexpr Dataset kMaterialDensity{"/materials/density", "kg/m^3", "density"};
inline constexpr Dataset kMaterialKn{"/materials/kn", "N/m", "normal spring stiffness"};
inline constexpr Dataset kMaterialKs{"/materials/ks", "N/m", "tangential spring stiffness"};
inline constexpr Dataset kMaterialFriction{"/materials/friction_angle", "deg", "friction angle"};
inline constexpr Dataset kMaterialCohesion{"/materials/cohesion", "N", "cohesion (Zhao eq. 35)"};
inline constexpr Dataset kMaterialNormalDamping{"/materials/normal_damping", "1",
                                                "viscous normal damping, fraction of critical"};
inline constexpr Dataset kMaterialLocalDamping{"/materials/local_damping", "1",
                                               "local non-viscous damping coefficient"};
inline constexpr Dataset kMaterialPenalty{"/materials/penalty", "Pa",
                                          "normal penalty of the potential kernels (Zhao eq. 13)"};
inline constexpr Dataset kMaterialJkn{"/materials/jkn", "Pa/m",
                                      "normal stiffness per area of face contacts (0: kn)"};
inline constexpr Dataset kMaterialJks{"/materials/jks", "Pa/m",
                                      "shear stiffness per area of face contacts (0: ks)"};
inline constexpr Dataset kInteractionPair{"/materials/interaction/pair", "",
                                          "material indices (a, b) of each explicit pair"};
inline constexpr Dataset kInteractionKn{"/materials/interaction/kn", "N/m", "normal stiffness"};
inline constexpr Dataset kInteractionKs{"/materials/interaction/ks", "N/m", "tangential stiffness"};
inline constexpr Dataset kInteractionFriction{"/materials/interaction/friction_angle", "deg",
                                              "friction angle"};
inline constexpr Dataset kInteractionCohesion{"/materials/interaction/cohesion", "N", "cohesion"};
inline constexpr Dataset kInteractionNormalDamping{"/materials/interaction/normal_damping", "1",
                                                   "viscous normal damping"};
inline constexpr Dataset kInteractionPenalty{"/materials/interaction/penalty", "Pa",
                                             "normal penalty"};
inline constexpr Dataset kInteractionJkn{"/materials/interaction/jkn", "Pa/m",
                                         "normal stiffness per area"};
inline constexpr Dataset kInteractionJks{"/materials/interaction/jks", "Pa/m",
                                         "shear stiffness per area"};

// --- /domain
// --------------------------------------------------------------------------------------
// --- /bolts: the state of every [[bolt]] at every joint it crosses (version 6), replicated; rows
// are the bolts in file order, each bolt's joints from its start (sim/bolts.h)
inline constexpr Dataset kBoltAxialPlastic{"/bolts/axial_plastic", "m",
                                           "plastic elongation at the joint (shortening < 0)"};
inline constexpr Dataset kBoltShearPlastic{"/bolts/shear_plastic", "m",
                                           "plastic shear slip at the joint, world frame"};
inline constexpr Dataset kBoltBroken{"/bolts/broken", "", "1 if the bolt broke at the joint"};

inline constexpr Dataset kDomainLo{"/domain/lo", "m", "lower corner of the domain box"};
inline constexpr Dataset kDomainHi{"/domain/hi", "m", "upper corner of the domain box"};
inline constexpr Dataset kDomainBlocks{"/domain/blocks", "", "block counts along x, y, z"};
inline constexpr Dataset kDomainPeriodic{"/domain/periodic", "", "1 if periodic along x, y, z"};
inline constexpr Dataset kDomainRankMap{"/domain/rank_map", "",
                                        "rank of each block (b = ix + nx (iy + ny iz))"};

// --- /particles: replicated (fixed/driven) rows first
// ---------------------------------------------
inline constexpr Dataset kUid{"/particles/uid", "", "global particle id"};
inline constexpr Dataset kShape{"/particles/shape", "", "row of /shapes"};
inline constexpr Dataset kMaterial{"/particles/material", "", "row of /materials"};
inline constexpr Dataset kFlags{"/particles/flags", "", "bit 1: fixed, bit 2: driven"};
inline constexpr Dataset kDriver{"/particles/driver", "", "index of the scene's driver, or -1"};
inline constexpr Dataset kPosition{"/particles/position", "m", "centroid, world frame"};
inline constexpr Dataset kOrientation{"/particles/orientation", "",
                                      "unit quaternion w, x, y, z: body to world"};
inline constexpr Dataset kVelocity{"/particles/velocity", "m/s",
                                   "centroid velocity at t - dt/2 (leapfrog)"};
inline constexpr Dataset kAngularMomentum{"/particles/angular_momentum", "kg m^2/s",
                                          "about the centroid, world frame, at t - dt/2"};

// --- /contacts: one row per pair history
// ------------------------------------------------------------
inline constexpr Dataset kPair{"/contacts/pair", "", "uids (lo, hi), lo < hi"};
inline constexpr Dataset kShearForce{"/contacts/shear_force", "N",
                                     "tangential force on the lower-uid particle, world frame"};
inline constexpr Dataset kNormal{"/contacts/normal", "", "unit contact normal of the last step"};
inline constexpr Dataset kWarmDirection{"/contacts/warm_direction", "",
                                        "kernel warm start: separating axis or plane normal"};
inline constexpr Dataset kWarmPoint{"/contacts/warm_point", "m",
                                    "kernel warm start: a point on the last common plane"};
inline constexpr Dataset kWarmValid{"/contacts/warm_valid", "", "1 if the warm start may be used"};
inline constexpr Dataset kKernelReserved{"/contacts/kernel_reserved", "",
                                         "reserved word of the kernel state"};
inline constexpr Dataset kTouching{"/contacts/touching", "", "1 if in contact at the last step"};

// --- /subcontacts: one row per sub-contact history (sub-contact model; format version 2)
// ---------------------------------------------------------
inline constexpr Dataset kSubPair{"/subcontacts/pair", "", "uids (lo, hi) of the pair, lo < hi"};
inline constexpr Dataset kSubFeature{
    "/subcontacts/feature", "",
    "features of lo (high 32 bits) and hi (low 32 bits): (type << 30) | index, type 1 vertex, "
    "2 edge, 3 face"};
inline constexpr Dataset kSubShearForce{"/subcontacts/shear_force", "N",
                                        "tangential force on the lower-uid particle, world frame"};
inline constexpr Dataset kSubNormal{"/subcontacts/normal", "",
                                    "unit normal of the sub-contact at the last step"};
inline constexpr Dataset kSubLawState{
    "/subcontacts/law_state", "",
    "the joint law's history values of the sub-contact, in its history columns' order (0 for "
    "material pairs and coulomb joints; docs/checkpoint.md, version 5)"};

// Bytes of one row of the particle and pair tables (all columns).
inline constexpr std::size_t kParticleRowBytes = 8 + 4 * 4 + 13 * 8;  // uid, 4 ints, 13 doubles
inline constexpr std::size_t kPairRowBytes = 2 * 8 + 12 * 8 + 3 * 4;  // pair, 4 vectors, 3 words
inline constexpr std::size_t kSubRowBytes = 3 * 8 + 8 * 8;  // pair, feature, 2 vectors, law state

/// Rows of a table packed (or unpacked) and hashed together, so that the block stays in cache.
inline constexpr std::uint64_t kBlockRows = 4096;

}  // namespace polydem::checkpoint::layout
