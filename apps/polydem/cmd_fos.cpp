// polydem fos SCENE --out DIR: the factor of safety of a scene by strength reduction
// (sim/fos.h), its trials spread over groups of the launched ranks.
#include <cstdio>

#include "commands.h"
#include "fos_files.h"
#include "polydem/contact/contact.h"
#include "polydem/core/logging.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/strings.h"
#include "polydem/particles/material.h"
#include "polydem/run/fos.h"
#include "polydem/scene/scene_reader.h"

namespace polydem::app {

namespace {

void usage() {
  std::printf(
      "usage: [mpirun -n N] polydem fos SCENE.toml --out DIR [options]\n"
      "Factor of safety by strength reduction: tan(friction angle) and cohesion of the scene's\n"
      "[fos] interactions (default: every material pair) are divided by F; a trial at F is\n"
      "stable when the mean speed of the free blocks falls below the speed limit after the\n"
      "settling time, before their mean displacement passes the limit. F is bisected to the\n"
      "resolution; the N ranks run N / ranks-per-trial trials side by side.\n"
      "  --ranks-per-trial K   ranks of each trial (default 1; must divide N)\n"
      "  --resolution R        width of the final bracket in F (overrides [fos] resolution)\n"
      "  --f-min A, --f-max B  the range searched (overrides [fos] f_min, f_max)\n"
      "  --max-time T          longest trial in simulated seconds (overrides [fos] max_time)\n"
      "  --kernel NAME         another contact kernel\n"
      "  --contact-model M     sub-contacts (default) or point (the scene's otherwise)\n"
      "  --quiet               only the result, warnings and errors\n"
      "writes DIR/fos.json (factor_of_safety, critical_friction_angle_deg, bracket, every\n"
      "trial's F, outcome, displacement and time), DIR/fos_trials.csv and DIR/fos.svg\n"
      "(mean displacement against time per trial). Settings: docs/scene-format.md, [fos].\n");
}

}  // namespace

int fosCommand(int argc, char** argv) {
  Args args(argc, argv, {"help", "quiet"});
  if (args.flag("help") || args.positional().size() != 1) {
    usage();
    return args.flag("help") ? 0 : 2;
  }
  const std::string out = args.value("out", "");
  if (out.empty()) throw UsageError("polydem fos needs --out DIR");
  const long long per_trial = args.integer("ranks-per-trial", 1, 1);
  const auto resolution = args.value("resolution");
  const auto f_min = args.value("f-min");
  const auto f_max = args.value("f-max");
  const auto max_time = args.value("max-time");
  const auto kernel = args.value("kernel");
  const auto contact_model = args.value("contact-model");
  const bool quiet = args.flag("quiet");
  io::Scene scene = io::readScene(args.positional()[0]);
  io::FosSpec& f = scene.fos;
  if (resolution) f.resolution = args.number("resolution", 0.0);
  if (f_min) f.f_min = args.number("f-min", 0.0);
  if (f_max) f.f_max = args.number("f-max", 0.0);
  if (max_time) f.max_time = args.number("max-time", 0.0);
  args.rejectUnknown();
  if (!(f.resolution > 0)) throw UsageError("--resolution must be > 0");
  if (!(f.f_min > 0) || !(f.f_max > f.f_min)) throw UsageError("need 0 < --f-min < --f-max");
  if (f.max_time && !(*f.max_time > 0)) throw UsageError("--max-time must be > 0");
  const int ranks = mpi::size();
  if (per_trial < 1 || ranks % per_trial != 0) {
    throw UsageError(cat("--ranks-per-trial ", per_trial, " must divide the ", ranks, " ranks"));
  }
  if (kernel) {
    contact::makeKernel(*kernel);  // throws with the list of known kernels
    scene.kernel = *kernel;
  }
  if (contact_model) {
    if (const auto e = io::unknownContactModel(*contact_model); !e.empty()) throw UsageError(e);
    scene.contact_model = *contact_model;
  }
  if (quiet) log::setLevel(log::Level::kWarning);
  const sim::FosCriterion criterion = sim::fosCriterion(scene);
  const int groups = ranks / static_cast<int>(per_trial);
  log::info(cat("fos: ", scene.id, " (", scene.file, "), kernel ", scene.kernel, ", contact model ",
                scene.contact_model, "; F in [", num(f.f_min), ", ", num(f.f_max), "] to ",
                num(f.resolution), "; ", groups, " trial(s) at a time on ", per_trial,
                " rank(s) each; stable when the mean speed < ", num(criterion.speed_limit),
                " m/s after ", num(criterion.settle_time),
                " s, failed when the mean displacement > ", num(criterion.displacement_limit),
                " m or still moving at ", num(criterion.max_time), " s"));
  const sim::FosResult result = sim::findFactorOfSafety(scene, criterion, groups, MPI_COMM_WORLD);
  if (mpi::rank() == 0) {
    const auto factor = result.factor();
    if (factor) {
      std::printf("factor of safety %s (stable at F = %s, failed at F = %s; resolution %s)\n",
                  num(*factor).c_str(), num(*result.stable).c_str(), num(*result.failed).c_str(),
                  num(result.resolution).c_str());
      const auto pairs = sim::reducedPairs(scene);
      particles::MaterialTable table;
      for (const auto& m : scene.materials) table.add(m);
      for (const auto& i : scene.interactions) table.setInteraction(i.a, i.b, i.properties);
      table.finalize();
      for (const auto& [a, b] : pairs) {
        const double phi = table.pair(a, b).friction_angle;
        std::printf("critical friction angle %s deg for %s/%s (%s deg divided by F)\n",
                    num(reducedFrictionAngle(phi, *factor)).c_str(),
                    scene.materials[a].name.c_str(), scene.materials[b].name.c_str(),
                    num(phi).c_str());
      }
    } else {
      std::printf("factor of safety not bracketed: %s\n", result.note.c_str());
    }
    if (factor && !result.note.empty()) std::printf("note: %s\n", result.note.c_str());
    writeFosFiles(out, scene, criterion, result);
    log::info("wrote " + out + "/fos.json, fos_trials.csv, fos.svg");
  }
  return 0;
}

}  // namespace polydem::app
