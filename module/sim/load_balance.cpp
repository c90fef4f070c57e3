#include "polydem/sim/load_balance.h"

#include <cmath>
#include <string>
#include <utility>

namespace polydem::sim {

namespace {

double sixtyFourths(double x) {
  return std::round(x * 64.0) / 64.0;
}

}  // namespace

double LoadModel::pairCost(bool touching, int subcontacts) const {
  return sixtyFourths(evaluated_pair + (touching ? touching_pair + subcontact * subcontacts : 0));
}

LoadModel loadModelFor(std::string_view kernel) {
  // Touching face-face cubes per second (README's kernel table) relative to gjk-epa-ipm's.
  static const std::pair<std::string_view, double> kTouching[] = {
      {"gjk-epa", 1.0}, {"gjk-epa-ipm", 1.75},        {"fcp", 2.0},    {"fcp-ipm", 2.0},
      {"lp", 0.5},      {"distance-potential", 20.0}, {"fdem", 160.0},
  };
  LoadModel m;
  for (const auto& [name, cost] : kTouching) {
    if (name == kernel) m.touching_pair = cost;
  }
  return m;
}

namespace {

/// Visits this rank's particles and pairs: visit(cost, a, b, pair, sampled), where `sampled`
/// says whether this rank samples the item (every pair is sampled on one rank only: that of its
/// lower-uid particle, or of its free particle when the other is a replicated body) and `pair`
/// whether both positions count (false for a particle or a pair with a replicated body).
template <typename Visit>
void visitWork(const particles::ParticleStorage& storage, const std::vector<PairWork>& work,
               const LoadModel& model, Visit&& visit) {
  for (std::size_t i = 0; i < storage.localCount(); ++i) {
    if (storage[i].isFree()) visit(model.particle, i, i, false, true);
  }
  for (const PairWork& w : work) {
    const double cost = model.pairCost(w.has(PairWork::kTouching), w.subcontacts);
    const bool a_global = storage[w.stored_a].isGlobal();
    if (w.has(PairWork::kAFree)) {  // A is ours and free
      const bool b_global = storage[w.stored_b].isGlobal();
      visit(cost, w.stored_a, w.stored_b, !b_global, true);
    } else if (a_global && w.has(PairWork::kBFree)) {  // a replicated body and our free B
      visit(cost, w.stored_b, w.stored_b, false, true);
    } else {  // A is a ghost: its owner evaluates the pair too and samples it
      visit(cost, w.stored_a, w.stored_b, false, false);
    }
  }
}

}  // namespace

LoadSample sampleLoad(const particles::ParticleStorage& storage, const std::vector<PairWork>& work,
                      const LoadModel& model) {
  LoadSample s;
  visitWork(storage, work, model,
            [&](double cost, std::size_t a, std::size_t b, bool pair, bool sampled) {
              s.work.done += cost;
              if (!sampled) return;
              s.work.unique += cost;
              s.items.push_back(
                  {storage[a].position, pair ? storage[b].position : Vec3::Zero(), cost, pair});
            });
  return s;
}

StepWork stepWork(const particles::ParticleStorage& storage, const std::vector<PairWork>& work,
                  const LoadModel& model) {
  StepWork w;
  visitWork(storage, work, model, [&](double cost, std::size_t, std::size_t, bool, bool sampled) {
    w.done += cost;
    if (sampled) w.unique += cost;
  });
  return w;
}

domain::BlockLoads binLoad(const domain::BlockForest& forest, const LoadSample& sample) {
  domain::BlockLoads loads(forest.numBlocks());
  for (const auto& item : sample.items) {
    const int a = forest.blockOf(item.a);
    if (a < 0) continue;
    const int b = item.pair ? forest.blockOf(item.b) : a;
    loads.addPair(a, b < 0 ? a : b, item.cost);
  }
  loads.merge();
  return loads;
}

}  // namespace polydem::sim
