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
  std::uint64_t shapes =
      capacityBytes(shapes_) + capacityBytes(shape_frames_) + capacityBytes(densities_);
  for (const auto& s : shapes_) shapes += shapeBytes(s);
  const ContactPhase::Memory phase = contact_phase_.memory();
  const std::uint64_t broadphase = broadphase_->heapBytes() + cell_order_.heapBytes() +
                                   capacityBytes(candidates_) + capacityBytes(early_candidates_) +
                                   capacityBytes(centers_) + capacityBytes(radii_) +
                                   capacityBytes(uids_) + capacityBytes(active_);
  return {
      {"particles", "particle state, uid index", storage_.stateBytes()},
      {"shapes", "shape table (vertices, faces, edges, adjacency)", shapes},
      {"scene", "the setup's particle and shape lists, kept by the simulation", sceneBytes(scene_)},
      {"broadphase", "grids, bounding spheres, candidate pairs", broadphase},
      {"pair_list", "candidate pairs in key order and their sort", phase.pair_list},
      {"history_pairs", "contact history: pairs (one table, rebuilt in place)",
       history_.pairBytes() + phase.history_pairs},
      {"history_subs", "contact history: sub-contacts (one table, rebuilt in place)",
       history_.subBytes() + phase.history_subs},
      {"kernel_caches", "per particle: rotations, world vertices and normals, boxes, Bodies",
       storage_.derivedBytes() + phase.filter},
      {"records", "contact records (output, monitors, load model), early results",
       phase.records + phase.early},
      {"forces", "per-particle force accumulators", capacityBytes(forces_)},
      {"exchange", "ghost and migration buffers, channels", exchange_.heapBytes()},
  };
}

}  // namespace polydem::sim
