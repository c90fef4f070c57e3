// Simulation::memoryUse: the rank's heap by structure, from capacities (sim/memory_use.h).
#include "polydem/core/memory.h"
#include "polydem/sim/simulation.h"

namespace polydem::sim {

namespace {

std::uint64_t shapeBytes(const geometry::BodyShape& s) {
  const auto& p = s.polyhedron;
  std::uint64_t bytes = s.name.capacity() > 15 ? s.name.capacity() + 1 : 0;
  bytes += capacityBytes(s.face_plane) + capacityBytes(p.vertices()) + capacityBytes(p.faces()) +
           capacityBytes(p.edges()) + capacityBytes(p.vertexEdges()) +
           capacityBytes(p.vertexFaces()) + capacityBytes(p.vertexNeighbours()) +
           capacityBytes(p.axisFaces()) + capacityBytes(p.axisEdges());
  for (const auto& f : p.faces()) bytes += capacityBytes(f.vertices) + capacityBytes(f.edges);
  return bytes;
}

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
  std::uint64_t shapes = capacityBytes(state_.shapes) + capacityBytes(state_.shape_frames) +
                         capacityBytes(state_.densities);
  for (const auto& s : state_.shapes) shapes += shapeBytes(s);
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
      {"records", "contact records (output, monitors, load model), early results",
       phase.records + phase.early},
      {"forces", "per-particle force accumulators", capacityBytes(state_.forces)},
      {"exchange", "ghost and migration buffers, channels", state_.exchange.heapBytes()},
  };
}

}  // namespace polydem::sim
