// The XDMF (version 2) descriptions of a run's HDF5 snapshots (output/snapshot_h5.h): one temporal
// collection per kind, DIR/snapshots.xmf for the blocks and DIR/contacts.xmf for the contact
// points, each listing every snapshot file with its time. The XML only points into the HDF5
// files ("snapshots/snapshot_S.h5:/mesh/points"); ParaView's and VTK's XDMF readers load the
// data from there. Blocks are a "Mixed" topology of polygons (each face one cell: type 3, vertex
// count, vertex indices), so the particle fields are cell data repeated on each face, as in the
// VTK snapshots.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace polydem::output {

/// What the collections need to know of one snapshot file.
struct XdmfSnapshot {
  double time = 0.0;
  std::string file;  // relative to the .xmf files' directory
  std::uint64_t points = 0, faces = 0, topology = 0, contacts = 0;
};

/// The .xmf of the blocks: for each snapshot (by step) a grid of the faces with the cell data
/// `fields` (names of setup::kParticleFields).
std::string xdmfParticleCollection(const std::map<std::int64_t, XdmfSnapshot>& snapshots,
                                   const std::vector<std::string>& fields);

/// The .xmf of the contacts: a grid of points (one vertex cell each) with the point data
/// `fields` (names of setup::kContactFields); snapshots without contacts are left out (an empty
/// grid is refused by some readers).
std::string xdmfContactCollection(const std::map<std::int64_t, XdmfSnapshot>& snapshots,
                                  const std::vector<std::string>& fields);

}  // namespace polydem::output
