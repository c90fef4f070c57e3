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
void visitWork(const particles::ParticleStorage& storage, const std::vector<ContactRecord>& records,
               const LoadModel& model, Visit&& visit) {
  for (std::size_t i = 0; i < storage.localCount(); ++i) {
    if (storage[i].isFree()) visit(model.particle, i, i, false, true);
  }
  for (const ContactRecord& r : records) {
    const double cost = model.pairCost(r.touching, r.subcontacts);
    const bool a_global = storage[r.stored_a].isGlobal();
    if (r.a >= 0) {  // A is ours and free
      const bool b_global = storage[r.stored_b].isGlobal();
      visit(cost, r.stored_a, r.stored_b, !b_global, true);
    } else if (a_global && r.b >= 0) {  // a replicated body and our free B
      visit(cost, r.stored_b, r.stored_b, false, true);
    } else {  // A is a ghost: its owner evaluates the pair too and samples it
      visit(cost, r.stored_a, r.stored_b, false, false);
    }
  }
}

}  // namespace

LoadSample sampleLoad(const particles::ParticleStorage& storage,
                      const std::vector<ContactRecord>& records, const LoadModel& model) {
  LoadSample s;
  visitWork(storage, records, model,
            [&](double cost, std::size_t a, std::size_t b, bool pair, bool sampled) {
              s.work.done += cost;
              if (!sampled) return;
              s.work.unique += cost;
              s.items.push_back(
                  {storage[a].position, pair ? storage[b].position : Vec3::Zero(), cost, pair});
            });
  return s;
}

StepWork stepWork(const particles::ParticleStorage& storage,
                  const std::vector<ContactRecord>& records, const LoadModel& model) {
  StepWork w;
  visitWork(storage, records, model,
            [&](double cost, std::size_t, std::size_t, bool, bool sampled) {
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
