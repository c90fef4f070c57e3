// Where a [[bolt]] runs (docs/scene-format.md "Rock bolts"): the blocks its segment crosses, in
// order from its start, found once from the scene's initial geometry. Between two consecutive
// blocks the bolt crosses a joint; its crossing point there is fixed as a material point of each
// of the two blocks (in their body frames), so that the relative displacement of the two blocks at
// the joint is that of these two points. Fixed rock is a block like any other: it anchors the
// bolt and takes no force.
#pragma once

#include <functional>
#include <vector>

#include "polydem/core/types.h"
#include "polydem/particles/particle_storage.h"
#include "polydem/setup/setup.h"

namespace polydem::sim {

/// One joint a bolt crosses, between block `a` (nearer the bolt's start) and block `b`.
struct BoltCrossing {
  Uid a = 0, b = 0;
  Vec3 anchor_a = Vec3::Zero(), anchor_b = Vec3::Zero();  // the crossing point, body frames
  Vec3 axis_a = Vec3::UnitZ();  // the bolt's direction in a's body frame (a -> b)
  // The middle of the bolt's piece inside a and inside b (body frames): the ends of the line the
  // snapshots draw for this joint.
  Vec3 middle_a = Vec3::Zero(), middle_b = Vec3::Zero();
  Vec3 point = Vec3::Zero();  // the crossing point at the start, world frame (for messages)
};

/// A particle's initial pose and shape, as the simulation places it.
struct InitialBody {
  const geometry::BodyShape* shape = nullptr;
  Vec3 centroid = Vec3::Zero();
  Quat orientation = Quat::Identity();  // body -> world
  bool free = true;
};

/// The joints `bolt` crosses, in order from its start: between each two consecutive blocks its
/// segment passes through, unless both are fixed or driven (nothing moves there). `body(i)` gives
/// particle i of scene.particles. Throws InputError (the scene's file, the bolt's line, its name)
/// when the bolt lies in fewer than two blocks, or crosses no joint of a free block.
std::vector<BoltCrossing> boltCrossings(const setup::Setup& scene, const setup::BoltSpec& bolt,
                                        const std::function<InitialBody(std::size_t)>& body);

}  // namespace polydem::sim
