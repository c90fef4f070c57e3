#include "polydem/run/contact_sums.h"

#include <map>

#include "polydem/core/mpi_env.h"

namespace polydem::run {

namespace {

// A migrated particle's sums, as plain bytes for the gather.
struct MovedSums {
  Uid uid = 0;
  std::int32_t count = 0;
  double force[3] = {0.0, 0.0, 0.0};
};

}  // namespace

void sumContactsByParticle(const sim::Simulation& sim, std::vector<std::int32_t>& count,
                           std::vector<Vec3>& force) {
  const auto& storage = sim.particles();
  count.assign(storage.localCount(), 0);
  force.assign(storage.localCount(), Vec3::Zero());
  std::map<Uid, std::size_t> moved_slot;
  std::vector<MovedSums> moved;
  auto add = [&](Uid uid, const Vec3& f) {
    const int i = storage.indexOf(uid);
    if (i >= 0) {
      ++count[i];
      force[i] += f;
      return;
    }
    const auto [slot, fresh] = moved_slot.try_emplace(uid, moved.size());
    if (fresh) moved.push_back(MovedSums{uid});
    MovedSums& m = moved[slot->second];
    ++m.count;
    m.force[0] += f.x(), m.force[1] += f.y(), m.force[2] += f.z();
  };
  // a >= 0 (b >= 0): A (B) was ours and free in the contact phase; A is the lower uid.
  for (const auto& r : sim.contacts().records()) {
    if (!r.touching) continue;
    if (r.a >= 0) add(r.key.lo, r.force);
    if (r.b >= 0) add(r.key.hi, -r.force);
  }
  // A particle was owned by one rank in the contact phase, so its new owner held none of its
  // contacts as its own and receives the complete sum (0 + sum keeps the bits).
  for (const MovedSums& m : mpi::allgatherv(moved, sim.comm())) {
    const int i = storage.indexOf(m.uid);
    if (i < 0) continue;
    count[i] += m.count;
    force[i] += Vec3(m.force[0], m.force[1], m.force[2]);
  }
}

}  // namespace polydem::run
