// What a step costs, by where the work is: the load model that the decomposition is balanced by.
//
// A rank's step is dominated by its contact phase, and the contact phase by the kernel calls:
// one per evaluated pair, several times dearer when the pair touches (EPA, the IPM point, the
// potential's integral) and, as ExaDEM weighs its cells by contact type, dearer for some kernels
// than for others. Particle counts miss that: a settled pile has ten times the pairs per
// particle of a falling front. The costs below are rough microseconds on one core (from the
// P-PILE timings and the kernel throughput table of README.md); only their ratios matter. They
// are multiples of 1/64, so that block loads sum exactly in any order and a decomposition is the
// same whatever the order of the reductions.
//
// The work is sampled by position (LoadSample), so that it can be binned into any block forest:
// the current one, to see how unbalanced it is, or a candidate of other block counts.
#pragma once

#include <string_view>
#include <vector>

#include "polydem/domain/block_forest.h"
#include "polydem/domain/block_loads.h"
#include "polydem/particles/particle_storage.h"
#include "polydem/sim/contact_phase.h"

namespace polydem::sim {

struct LoadModel {
  double particle = 0.5;         // an owned free particle: derived data, broad phase, integration
  double evaluated_pair = 0.25;  // a pair through the kernel (separated: an early exit)
  double touching_pair = 1.75;   // the extra of a touching pair (the kernel's contact work)
  // The extra of each loaded sub-contact (contact/face/face_contact.h): its corner geometry, law
  // and history. Measured with `polydem bench contact-model` on the dense pack of 8,000 cubes: the
  // sub-contact model's contact phase costs 34.6 ms more than the point model's for 303,920
  // sub-contacts, 0.11 us each, against 1.35 us per touching gjk-epa-ipm pair (1.75 here).
  double subcontact = 0.140625;  // 9/64
  /// One evaluated pair's cost; `subcontacts` are its loaded sub-contacts (0 for the point model
  /// and the potential kernels).
  double pairCost(bool touching, int subcontacts = 0) const;
};

/// The model for a kernel: touching_pair from its throughput on touching cubes, relative to
/// gjk-epa-ipm's 1.75 (gjk-epa 1, lp 0.5, fcp and fcp-ipm 2, distance-potential 20, fdem 160).
LoadModel loadModelFor(std::string_view kernel);

/// The work of one contact phase on this rank.
struct StepWork {
  double done = 0.0;    // its particles and every pair it evaluated, border pairs included
  double unique = 0.0;  // its particles and the pairs it samples (below): summed over the
                        // ranks, the step's work done once, as one rank would do it
};

/// One rank's work of its last contact phase, by position. Every pair is sampled on one rank
/// only (that of its lower-uid particle, or of its free particle when the other is a replicated
/// body), so that the samples of all ranks add up to the work of the whole step once.
struct LoadSample {
  struct Item {
    Vec3 a, b;  // a particle (b unused) or the two particles of a pair
    double cost = 0.0;
    bool pair = false;  // false: a particle, or a pair with a replicated body (only `a` counts)
  };
  std::vector<Item> items;
  StepWork work;
};

/// The sample of the contact phase that produced `work`; call it before the storage changes
/// (the work entries hold storage indices).
LoadSample sampleLoad(const particles::ParticleStorage& storage, const std::vector<PairWork>& work,
                      const LoadModel& model);
/// LoadSample::work alone, without the sample.
StepWork stepWork(const particles::ParticleStorage& storage, const std::vector<PairWork>& work,
                  const LoadModel& model);

/// The sample binned into the blocks of `forest` (positions wrapped along periodic axes; items
/// outside the domain are left out: migration reports them), links merged.
domain::BlockLoads binLoad(const domain::BlockForest& forest, const LoadSample& sample);

}  // namespace polydem::sim
