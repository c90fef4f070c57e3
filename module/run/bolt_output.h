// The bolts in the snapshots (docs/output-files.md "Bolts"): with every snapshot of a scene with
// [[bolt]]s, rank 0 writes DIR/bolts/bolts_<step>.vtp, a VTK PolyData file with one line per joint
// of every bolt (from the middle of its piece in one block to the middle of its piece in the next)
// and the cell data axial_force (N, tension positive), shear_force (N), bolt (index in file
// order), joint (from the bolt's start, 1-based) and broken (0/1); DIR/bolts.pvd lists them in
// time for ParaView.
#pragma once

#include <mpi.h>

#include <string>
#include <utility>
#include <vector>

#include "polydem/sim/simulation.h"

namespace polydem::run {

class BoltOutput {
 public:
  /// Collective; nothing is written for a scene without bolts. Entries of an existing
  /// DIR/bolts.pvd (a restarted run) are kept up to the first snapshot written here.
  BoltOutput(const std::string& dir, const sim::Simulation& sim);
  /// The bolts at the current state (collective: gathers the bolted blocks' poses).
  void write(const sim::Simulation& sim);

 private:
  void writeFiles(const sim::Simulation& sim, const std::vector<sim::BoltLine>& lines);
  void writeCollection() const;

  std::string dir_;
  bool root_ = false;
  bool any_ = false;
  std::vector<std::pair<double, std::string>> entries_;  // time, file relative to dir_
  std::vector<std::string> kept_;  // <DataSet> lines of an earlier run's collection
  bool first_ = true;
};

}  // namespace polydem::run
