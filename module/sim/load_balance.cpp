#include "sim/load_balance.h"

#include <cmath>
#include <string>
#include <utility>

namespace polydem::sim {

namespace {

double sixtyFourths(double x) {
  return std::round(x * 64.0) / 64.0;
}

}  // namespace

double LoadModel::pairCost(bool touching, int contact_points) const {
  return sixtyFourths(evaluated_pair +
                      (touching ? touching_pair * std::max(1, contact_points) : 0));
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

LoadSample sampleLoad(const particles::ParticleStorage& storage,
                      const std::vector<ContactRecord>& records, const LoadModel& model) {
  LoadSample s;
  for (std::size_t i = 0; i < storage.localCount(); ++i) {
    if (!storage[i].isFree()) continue;
    s.items.push_back({storage[i].position, Vec3::Zero(), model.particle, false});
    s.work += model.particle;
  }
  for (const ContactRecord& r : records) {
    const double cost = model.pairCost(r.touching);
    s.work += cost;
    const auto& a = storage[r.stored_a];
    const auto& b = storage[r.stored_b];
    if (r.a >= 0) {  // A is ours and free: we sample the pair
      if (b.isGlobal()) {
        s.items.push_back({a.position, Vec3::Zero(), cost, false});
      } else {
        s.items.push_back({a.position, b.position, cost, true});
      }
    } else if (a.isGlobal() && r.b >= 0) {  // a replicated body and our free B
      s.items.push_back({b.position, Vec3::Zero(), cost, false});
    }  // else A is a ghost: its owner evaluates the pair too and samples it
  }
  return s;
}

double stepWork(const particles::ParticleStorage& storage,
                const std::vector<ContactRecord>& records, const LoadModel& model) {
  double work = 0.0;
  for (std::size_t i = 0; i < storage.localCount(); ++i)
    work += storage[i].isFree() ? model.particle : 0.0;
  for (const ContactRecord& r : records) work += model.pairCost(r.touching);
  return work;
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
