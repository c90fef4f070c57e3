// The mechanism of the failed trial just above the factor of safety (run/fos_mechanism.h).
#include "polydem/run/fos_mechanism.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <sstream>
#include <tuple>

#include "polydem/core/error.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/strings.h"
#include "polydem/output/output_file.h"
#include "polydem/run/checks.h"
#include "polydem/run/run_checkpoint.h"
#include "polydem/run/run_output.h"
#include "polydem/run/tracker.h"
#include "polydem/sim/simulation.h"

namespace polydem::run {

namespace {

// One particle's pose and size, as plain numbers to gather over the ranks.
struct PoseRow {
  Uid uid;
  double x, y, z, qw, qx, qy, qz;
  double size, radius;  // V^(1/3) and circumradius, m
  int free;
};

struct Pose {
  Vec3 x = Vec3::Zero();
  Quat q = Quat::Identity();
  double size = 0.0, radius = 0.0;
  bool free = false, known = false;
};

// Every particle's pose, by uid, on every rank (collective).
std::vector<Pose> gatherPoses(const sim::Simulation& sim) {
  std::vector<PoseRow> mine;
  const auto& storage = sim.particles();
  for (std::size_t i = 0; i < storage.localCount(); ++i) {
    const auto& p = storage[i];
    const auto& shape = *sim.shapes()[p.shape].polyhedron;
    const Quat& q = p.orientation;
    mine.push_back({p.uid, p.position.x(), p.position.y(), p.position.z(), q.w(), q.x(), q.y(),
                    q.z(), std::cbrt(shape.volume()), shape.circumradius(), p.isFree() ? 1 : 0});
  }
  std::vector<Pose> poses;
  for (const PoseRow& r : mpi::allgatherv(mine, sim.comm())) {
    if (r.uid >= poses.size()) poses.resize(r.uid + 1);
    poses[r.uid] = {
        Vec3(r.x, r.y, r.z), Quat(r.qw, r.qx, r.qy, r.qz), r.size, r.radius, r.free != 0, true};
  }
  return poses;
}

// Every touching contact once, on every rank (collective).
struct ContactRow {
  Uid lo, hi;
  double px, py, pz, nx, ny, nz, normal_force;
  std::int32_t joint;
};

std::vector<ContactRow> gatherContacts(const sim::Simulation& sim) {
  std::vector<ContactRow> mine;
  for (const auto& r : sim.contacts().records()) {
    if (!r.touching || !r.a_is_local) continue;
    mine.push_back({r.key.lo, r.key.hi, r.point.x(), r.point.y(), r.point.z(), r.normal.x(),
                    r.normal.y(), r.normal.z(), r.normal_force, r.joint});
  }
  auto all = mpi::allgatherv(mine, sim.comm());
  std::sort(all.begin(), all.end(), [](const ContactRow& a, const ContactRow& b) {
    return std::tie(a.lo, a.hi) < std::tie(b.lo, b.hi);
  });
  return all;
}

// Displacement of the material point of a body now at `p`, from `start` to `now`.
Vec3 pointDisplacement(const Pose& start, const Pose& now, const Vec3& p) {
  const Vec3 before = start.x + start.q * (now.q.conjugate() * (p - now.x));
  return p - before;
}

// The largest reach / size of the free blocks (collective).
double largestReachFraction(const sim::Simulation& sim, const std::vector<Pose>& start) {
  double local = 0.0;
  const auto& storage = sim.particles();
  for (std::size_t i = 0; i < storage.localCount(); ++i) {
    const auto& p = storage[i];
    if (!p.isFree() || p.uid >= start.size() || !start[p.uid].known) continue;
    const Pose& s = start[p.uid];
    const double reach = (p.position - s.x).norm() + rotationAngle(s.q, p.orientation) * s.radius;
    local = std::max(local, reach / s.size);
  }
  double global = 0.0;
  MPI_Allreduce(&local, &global, 1, MPI_DOUBLE, MPI_MAX, sim.comm());
  return global;
}

std::string interactionName(const setup::Setup& scene, int joint, int a, int b) {
  if (joint >= 0) return scene.joints[joint].name;
  return scene.materials[a].name + "/" + scene.materials[b].name;
}

// The measures of the header, from the poses at the start and the end and the contacts at the end.
class MechanismMeter {
 public:
  MechanismMeter(const setup::Setup& scene, const std::vector<Pose>& start,
                 const std::vector<Pose>& now, const std::vector<ContactRow>& contacts)
      : scene_(scene), start_(start), now_(now), contacts_(contacts) {
    material_.assign(now.size(), -1);
    label_.assign(now.size(), "");
    for (const auto& p : scene.particles) {
      if (p.uid < now.size()) {
        material_[p.uid] = p.material;
        label_[p.uid] = p.label;
      }
    }
    const Vec3 g = scene.gravity.norm() > 0 ? Vec3(scene.gravity.normalized()) : Vec3(0, 0, -1);
    up_ = -g;
  }

  void measure(FosMechanism& m) {
    slip_.assign(contacts_.size(), 0.0);
    for (std::size_t k = 0; k < contacts_.size(); ++k) slip_[k] = contactSlip(contacts_[k]);
    sumSlipByInteraction(m);
    classifyBlocks(m);
    m.summary = summary(m);
  }

 private:
  double contactSlip(const ContactRow& c) const {
    const Vec3 p(c.px, c.py, c.pz), n(c.nx, c.ny, c.nz);
    const Vec3 rel = pointDisplacement(start_[c.lo], now_[c.lo], p) -
                     pointDisplacement(start_[c.hi], now_[c.hi], p);
    return (rel - rel.dot(n) * n).norm();
  }

  // Whether contact k slips: a share of the largest slip, above the noise of its smaller block.
  bool slips(std::size_t k, double largest) const {
    const ContactRow& c = contacts_[k];
    const double size = std::min(now_[c.lo].size, now_[c.hi].size);
    return slip_[k] >= kMoveShare * largest && slip_[k] >= kRestFraction * size;
  }

  void sumSlipByInteraction(FosMechanism& m) {
    std::map<std::tuple<int, int, int>, FosSlip> by;
    const double largest = slip_.empty() ? 0.0 : *std::max_element(slip_.begin(), slip_.end());
    for (std::size_t k = 0; k < contacts_.size(); ++k) {
      const ContactRow& c = contacts_[k];
      const int a = std::min(material_[c.lo], material_[c.hi]);
      const int b = std::max(material_[c.lo], material_[c.hi]);
      const auto key = c.joint >= 0 ? std::make_tuple(c.joint, -1, -1) : std::make_tuple(-1, a, b);
      FosSlip& s = by[key];
      if (s.contacts == 0) {
        s.joint = c.joint;
        s.material_a = c.joint >= 0 ? -1 : a;
        s.material_b = c.joint >= 0 ? -1 : b;
        s.name = interactionName(scene_, c.joint, a, b);
      }
      ++s.contacts;
      s.slipping += slips(k, largest);
      s.total_slip += slip_[k];
      s.max_slip = std::max(s.max_slip, slip_[k]);
      interaction_of_.push_back(s.name);
    }
    for (auto& [key, s] : by) m.slips.push_back(s);
    std::stable_sort(m.slips.begin(), m.slips.end(), [](const FosSlip& x, const FosSlip& y) {
      return x.total_slip > y.total_slip;
    });
    if (!m.slips.empty() && m.slips.front().slipping > 0) m.governing = m.slips.front().name;
  }

  bool measured(Uid u) const {
    return now_[u].known && now_[u].free && u < start_.size() && start_[u].known;
  }

  double reachOf(Uid u) const {
    return (now_[u].x - start_[u].x).norm() +
           rotationAngle(start_[u].q, now_[u].q) * now_[u].radius;
  }

  void classifyBlocks(FosMechanism& m) {
    m.max_reach = 0.0;
    for (Uid u = 0; u < now_.size(); ++u) {
      if (measured(u)) m.max_reach = std::max(m.max_reach, reachOf(u));
    }
    for (Uid u = 0; u < now_.size(); ++u) {
      if (!measured(u)) continue;
      ++m.free_blocks;
      FosBlockMotion b;
      b.uid = u;
      b.label = label_[u];
      b.displacement = now_[u].x - start_[u].x;
      const double theta = rotationAngle(start_[u].q, now_[u].q);
      b.rotation_deg = radToDeg(theta);
      b.size = now_[u].size;
      const double d = b.displacement.norm(), turn = theta * now_[u].radius;
      b.reach = d + turn;
      if (!(b.reach >= kMoveShare * m.max_reach && b.reach >= kRestFraction * b.size)) continue;
      // The seat: the contact whose normal is nearest the vertical.
      double best = -1.0;
      for (std::size_t k = 0; k < contacts_.size(); ++k) {
        const ContactRow& c = contacts_[k];
        if (c.lo != u && c.hi != u) continue;
        ++b.contacts;
        const double vertical = std::abs(Vec3(c.nx, c.ny, c.nz).dot(up_));
        if (vertical > best) {
          best = vertical;
          b.seat_slip = slip_[k];
        }
      }
      if (b.contacts == 0) {
        b.mode = "falling";
      } else if (turn > kRotationShare * d) {
        b.mode = b.seat_slip < kPivotSlipShare * d ? "toppling" : "rotating";
      } else {
        b.mode = "sliding";
      }
      ++m.modes[b.mode];
      m.blocks.push_back(b);
    }
  }

  // Plane or wedge sliding: the normals of the slipping contacts of sliding blocks, weighted by
  // slip, in groups within 10 deg of one another; the groups holding a quarter of the slip or
  // more are the sliding planes. Returns their interactions (one or two), or none for more.
  std::vector<std::string> slidingPlanes(const FosMechanism& m) const {
    std::vector<char> sliding(now_.size(), 0);
    for (const auto& b : m.blocks) sliding[b.uid] = b.mode == "sliding";
    struct Group {
      Vec3 normal;
      double weight;
      std::string interaction;
    };
    std::vector<Group> groups;
    std::vector<std::size_t> order(contacts_.size());
    for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t x, std::size_t y) { return slip_[x] > slip_[y]; });
    double total = 0.0;
    const double largest = order.empty() ? 0.0 : slip_[order.front()];
    for (const std::size_t k : order) {
      const ContactRow& c = contacts_[k];
      if (!(sliding[c.lo] || sliding[c.hi]) || !slips(k, largest)) continue;
      const Vec3 n(c.nx, c.ny, c.nz);
      total += slip_[k];
      auto g = std::find_if(groups.begin(), groups.end(), [&](const Group& x) {
        return std::abs(x.normal.dot(n)) > std::cos(degToRad(10.0));
      });
      if (g == groups.end()) {
        groups.push_back({n, slip_[k], interaction_of_[k]});
      } else {
        g->weight += slip_[k];
      }
    }
    std::vector<std::string> planes;
    for (const Group& g : groups) {
      if (g.weight >= 0.25 * total) planes.push_back(g.interaction);
    }
    return planes.size() <= 2 ? planes : std::vector<std::string>{};
  }

  std::string summary(const FosMechanism& m) const {
    if (m.blocks.empty()) {
      return cat("no block moved more than ", num(kRestFraction),
                 " of its size after the trial's decision");
    }
    std::string mode;
    int count = 0;
    for (const char* k : {"sliding", "toppling", "rotating", "falling"}) {
      const auto it = m.modes.find(k);
      if (it != m.modes.end() && it->second > count) {
        mode = k;
        count = it->second;
      }
    }
    std::string on = m.governing.empty() ? "" : cat(" on '", m.governing, "'");
    if (mode == "sliding") {
      const std::vector<std::string> planes = slidingPlanes(m);
      if (planes.size() == 1) {
        mode = "plane sliding";
      } else if (planes.size() == 2) {
        mode = "wedge sliding";
        if (planes[0] != planes[1]) on = cat(" on '", planes[0], "' and '", planes[1], "'");
      }
    }
    std::string s = cat(mode, " of ", count, count == 1 ? " block" : " blocks", on);
    std::string others;
    for (const auto& [k, n] : m.modes) {
      if (mode.find(k) == std::string::npos) others += cat(others.empty() ? "" : ", ", n, " ", k);
    }
    return others.empty() ? s : cat(s, " (", others, ")");
  }

  const setup::Setup& scene_;
  const std::vector<Pose>& start_;
  const std::vector<Pose>& now_;
  const std::vector<ContactRow>& contacts_;
  std::vector<int> material_;
  std::vector<std::string> label_;
  std::vector<double> slip_;
  std::vector<std::string> interaction_of_;  // per contact
  Vec3 up_ = Vec3::UnitZ();
};

std::string blocksCsv(const FosMechanism& m) {
  std::ostringstream out;
  out << "uid,label,mode,dx,dy,dz,displacement,rotation_deg,size,reach,contacts,seat_slip\n";
  for (const auto& b : m.blocks) {
    out << b.uid << ',' << b.label << ',' << b.mode << ',' << num(b.displacement.x()) << ','
        << num(b.displacement.y()) << ',' << num(b.displacement.z()) << ','
        << num(b.displacement.norm()) << ',' << num(b.rotation_deg) << ',' << num(b.size) << ','
        << num(b.reach) << ',' << b.contacts << ',' << num(b.seat_slip) << '\n';
  }
  return out.str();
}

// Snapshots and series along the trial, the run-on past its decision, and the measures.
class MechanismObserver : public FosTrialObserver {
 public:
  MechanismObserver(const setup::Setup& scene, const FosCriterion& c, const FosTrial& failed,
                    FosMechanism& m, const std::function<void(sim::Simulation&)>& then)
      : scene_(scene), criterion_(c), failed_(failed), m_(m), then_(then) {}

  void started(sim::Simulation& sim) override {
    t0_ = sim.time();
    const std::vector<std::unique_ptr<Check>> none;
    output_ = std::make_unique<RunOutput>(m_.dir, sim, tracker_,
                                          std::vector<std::pair<Uid, std::string>>{}, none, true);
    snapshot(sim);
  }

  void checked(sim::Simulation& sim) override {
    const std::vector<std::unique_ptr<Check>> none;
    output_->writeSeries(sim, tracker_, none);
    if (sim.time() - t0_ >= next_snapshot_) snapshot(sim);
  }

  void decided(sim::Simulation& sim, const FosTrial& trial) override {
    m_.same_bits = trial.state_hash == failed_.state_hash;
    m_.decided_time = trial.time;
    const std::vector<Pose> at_decision = gatherPoses(sim);
    for (;;) {
      if (largestReachFraction(sim, at_decision) >= kRunOnFraction) {
        m_.stopped_by = "size";
        break;
      }
      if (sim.time() - t0_ >= criterion_.time_cap) {
        m_.stopped_by = "time_cap";
        break;
      }
      if (sim.time() - t0_ >= trial.time + criterion_.window) {
        m_.stopped_by = "window";
        break;
      }
      if (const int sig = stopSignalOnAnyRank(sim.comm())) {
        m_.stopped_by = signalName(sig);
        break;
      }
      for (std::int64_t i = 0; i < criterion_.check_every; ++i) sim.step();
      checked(sim);
    }
    output_->writeSnapshotOnce(sim);
    ++m_.snapshots;
    output_->close();
    m_.time = sim.time() - t0_;
    m_.steps = sim.stepCount();
    const std::vector<Pose> now = gatherPoses(sim);
    const std::vector<ContactRow> contacts = gatherContacts(sim);
    MechanismMeter(scene_, at_decision, now, contacts).measure(m_);
    if (then_) then_(sim);
  }

 private:
  void snapshot(sim::Simulation& sim) {
    output_->writeSnapshot(sim);
    ++m_.snapshots;
    next_snapshot_ += criterion_.max_time / kSnapshotsPerMaxTime;
  }

  const setup::Setup& scene_;
  const FosCriterion& criterion_;
  const FosTrial& failed_;
  FosMechanism& m_;
  const std::function<void(sim::Simulation&)>& then_;
  Tracker tracker_;
  std::unique_ptr<RunOutput> output_;
  double t0_ = 0.0, next_snapshot_ = 0.0;
};

}  // namespace

FosMechanism runFosMechanism(const setup::Setup& scene, const FosTrial& failed,
                             const FosCriterion& criterion, const std::string& dir, MPI_Comm comm,
                             const std::function<void(sim::Simulation&)>& then) {
  FosMechanism m;
  m.factor = failed.factor;
  m.dir = dir;
  setup::Setup shown = scene;
  shown.output.snapshot_format = "xdmf";  // what the picture and ParaView read
  MechanismObserver observer(shown, criterion, failed, m, then);
  const FosTrial t = runFosTrial(shown, failed.factor, criterion, comm, &observer);
  if (t.outcome == "interrupted") {
    m.stopped_by = "interrupted";
    m.summary = "the mechanism's trial was stopped by a signal before its decision";
    return m;
  }
  std::string error;
  if (mpi::rank(comm) == 0) {
    try {
      output::writeFileAtomic(dir + "/blocks.csv", blocksCsv(m));
    } catch (const Error& e) {
      error = e.what();
    }
  }
  output::throwIfAnyRankFailed(error, comm);
  return m;
}

}  // namespace polydem::run
