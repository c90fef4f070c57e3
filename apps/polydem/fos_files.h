// The files `polydem fos` writes into its output directory: fos.json (the result and every
// trial), fos_trials.csv (each trial's mean displacement and speed against time) and fos.svg
// (displacement against time, one line per trial, drawn without any plotting library).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "polydem/run/fos.h"
#include "polydem/run/fos_mechanism.h"
#include "polydem/setup/setup.h"

namespace polydem::app {

/// Writes the three files into `dir` (created if needed), each atomically. Rank 0 only.
/// `resume_command`: how to continue a search a signal stopped (empty when complete);
/// `mechanism`: that of the smallest failed trial, if it was run; `picture`: its PNG ("" none).
void writeFosFiles(const std::string& dir, const setup::Setup& scene,
                   const run::FosCriterion& criterion, const run::FosResult& result,
                   const std::string& resume_command, const run::FosMechanism* mechanism,
                   const std::string& picture);

/// The critical strength of each reduced joint and pair at `factor`, one line each, for the
/// console: "joint 'base': friction angle 19.8 deg (25 deg / F), cohesion 7.7 kPa (...)".
std::vector<std::string> criticalStrengthLines(const setup::Setup& scene, double factor);

/// A hash of a scene file's text, 16 hex digits: fos.json keeps it so that a continued search
/// runs the scene its trials ran.
std::string sceneHash(const std::string& text);

/// What `polydem fos --resume DIR` reads back from DIR/fos.json: the scene, the settings the
/// command line gave, and the search so far (every trial bit for bit).
struct FosRun {
  std::string scene_path;  // absolute
  std::string scene_hash;
  double f_min = 0.0, f_max = 0.0, resolution = 0.0;
  std::optional<double> max_time;
  std::string kernel, contact_model;
  bool complete = false;
  run::FosResult result;
};
/// Throws InputError naming DIR/fos.json if it is missing, unreadable or lacks a field.
FosRun readFosRun(const std::string& dir);

/// The friction angle (deg) of `phi_deg` reduced by `factor`: atan(tan(phi) / factor).
double reducedFrictionAngle(double phi_deg, double factor);

}  // namespace polydem::app
