// The files `polydem fos` writes into its output directory: fos.json (the result and every
// trial), fos_trials.csv (each trial's mean displacement and speed against time) and fos.svg
// (displacement against time, one line per trial, drawn without any plotting library).
#pragma once

#include <string>

#include "polydem/run/fos.h"
#include "polydem/setup/setup.h"

namespace polydem::app {

/// Writes the three files into `dir` (created if needed), each atomically. Rank 0 only.
void writeFosFiles(const std::string& dir, const io::Scene& scene,
                   const sim::FosCriterion& criterion, const sim::FosResult& result);

/// The friction angle (deg) of `phi_deg` reduced by `factor`: atan(tan(phi) / factor).
double reducedFrictionAngle(double phi_deg, double factor);

}  // namespace polydem::app
