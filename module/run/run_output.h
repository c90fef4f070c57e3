// Output of a run: the series.csv columns, ParaView snapshot batches (XDMF + HDF5 or VTK, as the
// scene's [output] snapshot_format says) and summary.json.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "polydem/output/series_writer.h"
#include "polydem/output/snapshot_h5.h"
#include "polydem/output/vtk_writer.h"
#include "polydem/run/bolt_output.h"
#include "polydem/run/checks.h"
#include "polydem/sim/simulation.h"

namespace polydem::run {

class RunOutput {
 public:
  /// Creates `dir` and the writers (collective). `monitored` are the uids whose state goes into
  /// series.csv, with their labels.
  RunOutput(const std::string& dir, sim::Simulation& sim, const Tracker& tracker,
            const std::vector<std::pair<Uid, std::string>>& monitored,
            const std::vector<std::unique_ptr<Check>>& checks, bool snapshots);

  /// A row of series.csv (collective: computes global monitors; a failed write throws on every
  /// rank).
  void writeSeries(sim::Simulation& sim, const Tracker& tracker,
                   const std::vector<std::unique_ptr<Check>>& checks);
  /// A snapshot of particles and contacts (collective).
  void writeSnapshot(const sim::Simulation& sim);
  /// writeSeries / writeSnapshot unless the last row / snapshot already holds this step of this
  /// stage (for the final state, which the observer may have written at its last step).
  void writeSeriesOnce(sim::Simulation& sim, const Tracker& tracker,
                       const std::vector<std::unique_ptr<Check>>& checks);
  void writeSnapshotOnce(const sim::Simulation& sim);
  /// Flushes and closes series.csv (collective: a failed write throws on every rank).
  void close();

 private:
  void facePressures(const sim::Simulation& sim, std::size_t i, const Mat3& rotation,
                     std::vector<double>& out);
  /// Stage and step of a written row or snapshot.
  struct Written {
    int stage = -1;
    std::int64_t step = -1;
    bool operator==(const Written&) const = default;
  };
  static Written labelOf(const sim::Simulation& sim);
  MPI_Comm comm_;
  Written last_series_, last_snapshot_;
  std::vector<std::pair<Uid, std::string>> monitored_;
  std::unique_ptr<output::SeriesWriter> series_;
  std::unique_ptr<output::SnapshotWriter> snapshots_;  // snapshot_format = "vtk"
  std::unique_ptr<output::XdmfSnapshotWriter> xdmf_;   // snapshot_format = "xdmf"
  std::unique_ptr<BoltOutput> bolts_;              // with either, for a scene with bolts
  std::vector<std::int32_t> contact_count_;        // per local particle, for the snapshot
  std::vector<Vec3> contact_force_;
  std::vector<Vec3> initial_positions_;  // by uid order of the scene, for displacement
  std::vector<double> row_;
  output::PolyhedraBatch batch_;
  output::ContactBatch contacts_;
  std::vector<Vec3> vertices_;
  std::vector<Vec3> normals_;
  std::vector<double> pressures_;  // per face of one particle: water pressure (Pa)
};

}  // namespace polydem::run
