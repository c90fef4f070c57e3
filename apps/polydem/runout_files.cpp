#include "runout_files.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "commands.h"
#include "picture.h"
#include "polydem/checkpoint/checkpoint.h"
#include "polydem/core/error.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/state_hash.h"
#include "polydem/core/strings.h"
#include "polydem/output/output_file.h"
#include "polydem/sim/simulation.h"

namespace polydem::app {

namespace {

using nlohmann::json;

// The rows of an earlier part's runout_series.csv before run-on time `before` (none if absent).
std::string earlierRows(const std::string& path, double before) {
  std::ifstream in(path);
  std::string line, rows;
  if (!std::getline(in, line)) return rows;  // the header
  while (std::getline(in, line)) {
    if (!line.empty() && std::stod(line.substr(0, line.find(','))) < before) rows += line + "\n";
  }
  return rows;
}

std::string seriesCsv(const run::RunoutResult& r, const std::string& earlier) {
  std::ostringstream out;
  out << "time,mean_displacement,mean_speed,speed_ratio\n" << earlier;
  for (const auto& s : r.series) {
    out << num(s.time) << ',' << num(s.mean_displacement) << ',' << num(s.mean_speed) << ','
        << num(s.speed_ratio) << '\n';
  }
  return out.str();
}

}  // namespace

run::RunoutSettings runoutSettings(const setup::Setup& scene, const RunoutOptions& options,
                                   const std::string& dir) {
  run::RunoutSettings s;
  const std::optional<double> cap = options.time_cap ? options.time_cap : scene.end_time;
  if (!cap || !(*cap > 0.0)) {
    throw UsageError(cat("the run-on of ", scene.file,
                         " needs a time cap: --runout-time T (the scene has no end_time)"));
  }
  s.time_cap = *cap;
  s.check_every = options.check_every;
  s.cell = options.cell;
  s.checkpoint_every = options.checkpoint_every.value_or(scene.checkpoint.every_steps);
  s.dir = dir;
  s.scene_text = scene.text;
  s.scene_file = scene.file;
  return s;
}

std::string runOnDynamics(const setup::Setup& scene) {
  std::string materials;
  for (const auto& m : scene.materials) {
    materials +=
        cat(materials.empty() ? "" : "; ", m.name, ": friction angle ", num(m.friction_angle),
            " deg, cohesion ", num(m.cohesion), " N, local damping ", num(m.local_damping),
            ", normal damping ", num(m.normal_damping));
  }
  return cat("the scene's own strengths and damping, unreduced (", materials, "; ",
             scene.interactions.size(), " [[interaction]](s) and ", scene.joints.size(),
             " [[joint]](s) as written, each joint's slip history carried on), not the trials' "
             "reduced strengths and static local damping");
}

run::RunoutResult runOutFrom(sim::Simulation& failing, const setup::Setup& scene,
                             const run::RunoutSettings& settings) {
  // The failing state handed over as a checkpoint in memory, continued with the scene's own
  // strengths and damping (the stored scene is the one written: a restart continues the same).
  run::RunoutProgress progress;
  progress.start_time = failing.time();
  // Its periodic checkpoints go into DIR/runout, which exists before the first one.
  if (!settings.dir.empty() && mpi::rank(failing.comm()) == 0) {
    std::filesystem::create_directories(settings.dir);
  }
  MPI_Barrier(failing.comm());
  const sim::CheckpointData data = failing.checkpoint(
      settings.scene_text, settings.scene_file, run::runoutStateJson(progress, settings, scene));
  sim::Simulation runout(scene, data, "the failed trial's state", failing.comm());
  return run::runRunout(runout, settings, progress);
}

json runoutJson(const run::RunoutResult& r, const std::string& resume_command,
                const std::string& picture) {
  const run::RunoutDeposit& d = r.deposit;
  return {
      {"at_rest", r.at_rest},
      {"stopped_by", r.stopped_by},
      {"rest_criterion",
       cat("every free block's speed (|v| + |w| R) below ", num(run::kRestSpeed),
           " sqrt(g s), s its size V^(1/3), at ", run::kRestChecks, " checks in a row")},
      {"time", r.time},
      {"steps", r.steps},
      {"state_hash", BitHasher::hex(r.state_hash)},
      {"max_speed_ratio", r.max_speed_ratio},
      {"failed_blocks", d.failed_blocks},
      {"free_blocks", d.free_blocks},
      {"failed_volume", d.failed_volume},
      {"failed_criterion", cat("free blocks whose centroid moved at least ",
                               num(run::kMovedFraction), " of their size from the scene's start")},
      {"direction", {d.direction.x(), d.direction.y()}},
      {"toe_start", d.toe_start},
      {"front_end", d.front_end},
      {"runout_distance", d.runout},
      {"largest_block_travel", d.max_travel},
      {"largest_block_travel_uid", d.max_travel_uid},
      {"deposit",
       {{"cell", d.cell},
        {"area", d.area},
        {"length", d.length},
        {"width", d.width},
        {"volume", d.volume},
        {"max_thickness", d.max_thickness},
        {"grid", {{"x0", d.x0}, {"y0", d.y0}, {"nx", d.nx}, {"ny", d.ny}}}}},
      {"files",
       {{"thickness", "thickness.csv"},
        {"series", "runout_series.csv"},
        {"picture", picture.empty() ? json() : json("thickness.png")},
        {"checkpoint", r.checkpoint.empty() ? json() : json("runout.h5")}}},
      {"resume", resume_command.empty() ? json() : json(resume_command)}};
}

json writeRunoutFiles(const std::string& dir, const run::RunoutResult& r,
                      const std::string& resume_command) {
  namespace fs = std::filesystem;
  fs::create_directories(dir);
  const std::string series = dir + "/runout_series.csv";
  const std::string earlier =
      r.series.empty() ? std::string() : earlierRows(series, r.series.front().time);
  output::writeFileAtomic(series, seriesCsv(r, earlier));
  output::writeFileAtomic(dir + "/thickness.csv", run::thicknessCsv(r.deposit));
  // The figures first: the picture's title reads them.
  output::writeFileAtomic(dir + "/runout.json", runoutJson(r, resume_command, "").dump(2) + "\n");
  const std::string picture = r.deposit.cells.empty() ? std::string() : plotThickness(dir);
  const json j = runoutJson(r, resume_command, picture);
  output::writeFileAtomic(dir + "/runout.json", j.dump(2) + "\n");
  return j;
}

void addRunout(const std::string& fos_dir, const run::RunoutResult& r, int ranks,
               const std::string& dynamics) {
  const std::string dir = fos_dir + "/runout";
  const std::string resume = r.checkpoint.empty()
                                 ? std::string()
                                 : cat("mpirun -n ", ranks, " polydem runout --resume ", dir);
  json j = writeRunoutFiles(dir, r, resume);
  j["dir"] = "runout";
  j["dynamics"] = dynamics;
  const std::string path = fos_dir + "/fos.json";
  std::ifstream in(path);
  json fos = json::parse(in);
  fos["runout"] = j;
  output::writeFileAtomic(path, fos.dump(2) + "\n");
  std::printf("%s\n", runoutLine(r, dir).c_str());
  std::printf("runout dynamics: %s\n", dynamics.c_str());
  if (!resume.empty()) std::printf("to continue the runout: %s\n", resume.c_str());
}

std::string runoutLine(const run::RunoutResult& r, const std::string& dir) {
  const run::RunoutDeposit& d = r.deposit;
  return cat("runout: ", r.at_rest ? "at rest" : "NOT at rest", " after ", num(r.time), " s (",
             r.stopped_by, "); ", d.failed_blocks, " of ", d.free_blocks,
             " blocks failed; runout distance ", num(d.runout), " m, largest block travel ",
             num(d.max_travel), " m; deposit ", num(d.area), " m^2 (", num(d.length), " m x ",
             num(d.width), " m), up to ", num(d.max_thickness), " m thick (", dir, ")");
}

}  // namespace polydem::app
