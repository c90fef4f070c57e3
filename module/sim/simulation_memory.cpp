// Simulation::memoryUse: the rank's heap by structure, from capacities (sim/memory_use.h).
#include "polydem/core/memory.h"
#include "polydem/geometry/shape_memory.h"
#include "polydem/sim/simulation.h"

namespace polydem::sim {

namespace {

// The particle and shape lists of the setup the simulation keeps (its other members are a few
// strings and per-material tables).
std::uint64_t sceneBytes(const setup::Setup& scene) {
  std::uint64_t bytes = capacityBytes(scene.particles) + capacityBytes(scene.shapes);
  for (const auto& p : scene.particles)
    bytes += p.label.capacity() > 15 ? p.label.capacity() + 1 : 0;
  for (const auto& s : scene.shapes)
    bytes += capacityBytes(s.vertices) + capacityBytes(s.face_planes);
  return bytes;
}

}  // namespace

MemoryUse Simulation::memoryUse() const {
  // The shape table by part (a polyhedron shared by several shapes counted once).
  std::uint64_t shapes = capacityBytes(state_.shapes) -
                         state_.shapes.size() * sizeof(geometry::BodyShape) +
                         capacityBytes(state_.shape_frames) + capacityBytes(state_.densities);
  for (const auto& part : geometry::shapeMemory(state_.shapes)) shapes += part.bytes;
  const ContactPhase::Memory phase = state_.contact_phase.memory();
  const std::uint64_t broadphase = state_.broadphase->heapBytes() + state_.cell_order.heapBytes() +
                                   capacityBytes(state_.candidates) +
                                   capacityBytes(state_.early_candidates) +
                                   capacityBytes(state_.centers) + capacityBytes(state_.radii) +
                                   capacityBytes(state_.uids) + capacityBytes(state_.active);
  return {
      {"particles", "particle state, uid index", state_.storage.stateBytes()},
      {"shapes", "shape table (vertices, faces, edges, adjacency)", shapes},
      {"scene", "the setup's particle and shape lists, kept by the simulation",
       sceneBytes(state_.scene)},
      {"broadphase", "grids, bounding spheres, candidate pairs", broadphase},
      {"pair_list", "candidate pairs in key order and their sort", phase.pair_list},
      {"history_pairs", "contact history: pairs (one table, rebuilt in place)",
       state_.history.pairBytes() + phase.history_pairs},
      {"history_subs", "contact history: sub-contacts (one table, rebuilt in place)",
       state_.history.subBytes() + phase.history_subs},
      {"kernel_caches", "per particle: rotations, world vertices and normals, boxes, Bodies",
       state_.storage.derivedBytes() + phase.filter},
      {"pair_work", "per evaluated pair: storage indices and flags (load model, contact count)",
       phase.work},
      {"records", "contact records (snapshots, tracked particles, checks), when kept",
       phase.records},
      {"early", "pairs evaluated while the exchange is in flight (several ranks)", phase.early},
      {"forces", "per-particle force accumulators", capacityBytes(state_.forces)},
      {"exchange", "ghost and migration buffers, channels", state_.exchange.heapBytes()},
  };
}

}  // namespace polydem::sim
