#include "polydem/run/checks.h"
#include "polydem/run/check_registry.h"

#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <sstream>

#include "polydem/core/error.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/strings.h"
#include "polydem/run/motion_checks.h"
#include "polydem/scene/check_kinds.h"
#include "polydem/sim/simulation.h"

namespace polydem::run {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// --- parameters of a check --------------------------------------------------------------------

// The scene reader has checked every parameter against its kind's declaration
// (scene/check_kinds.h): a kind reads only what it declares, so that the declarations stay the
// whole truth.
class Params {
 public:
  Params(const setup::Setup& scene, const setup::CheckSpec& spec) : scene_(scene), spec_(spec) {}

  [[noreturn]] void fail(const std::string& message) const {
    throw InputError(scene_.file, spec_.line,
                     cat("[[check]] '", spec_.name, "' (kind ", spec_.kind, "): ", message));
  }
  double number(const std::string& key, std::optional<double> fallback = std::nullopt) const {
    declared(key);
    const auto it = spec_.numbers.find(key);
    if (it == spec_.numbers.end()) {
      if (fallback) return *fallback;
      fail("needs the number '" + key + "'");
    }
    if (it->second.size() != 1) fail("'" + key + "' must be a single number");
    return it->second[0];
  }
  std::optional<Vec3> vector(const std::string& key, bool required = false) const {
    declared(key);
    const auto it = spec_.numbers.find(key);
    if (it == spec_.numbers.end()) {
      if (required) fail("needs the vector '" + key + "' = [x, y, z]");
      return std::nullopt;
    }
    if (it->second.size() != 3) fail("'" + key + "' must be a vector [x, y, z]");
    const Vec3 v(it->second[0], it->second[1], it->second[2]);
    if (!(v.norm() > 0)) fail("'" + key + "' must not be zero");
    return v.normalized();
  }
  std::string text(const std::string& key, const std::string& fallback = "") const {
    declared(key);
    const auto it = spec_.strings.find(key);
    return it == spec_.strings.end() ? fallback : it->second;
  }
  /// The particles named by `particle` (one label, or several separated by commas).
  std::vector<Uid> particles(Tracker& tracker) const {
    const std::string list = text("particle");
    if (list.empty()) fail("needs 'particle' = \"label\" (or \"a,b,c\")");
    std::vector<Uid> uids;
    std::stringstream in(list);
    std::string label;
    while (std::getline(in, label, ',')) {
      label.erase(0, label.find_first_not_of(' '));
      label.erase(label.find_last_not_of(' ') + 1);
      const Uid uid = uidOfLabel(scene_, label);
      if (uid == 0) fail("no particle is labelled '" + label + "'");
      tracker.track(uid);
      uids.push_back(uid);
    }
    return uids;
  }

 private:
  void declared(const std::string& key) const {
    const scene::CheckKind* kind = scene::findCheckKind(spec_.kind);
    if (!kind || !scene::findCheckParam(*kind, key)) {
      throw Error(cat("check kind '", spec_.kind, "' reads '", key,
                      "', which scene/check_kinds.cpp does not declare"));
    }
  }

  const setup::Setup& scene_;
  const setup::CheckSpec& spec_;
};

std::string columnName(const std::string& name) {
  std::string out;
  for (char c : name) out += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  return out;
}

// --- kinds ------------------------------------------------------------------------------------

// Max (or final) displacement of particles, optionally along a direction.
class DisplacementCheck : public Check {
 public:
  DisplacementCheck(const setup::Setup& scene, const setup::CheckSpec& spec, Tracker& t)
      : Check(spec) {
    Params p(scene, spec);
    uids_ = p.particles(t);
    direction_ = p.vector("direction");
    final_ = p.text("at", "max") == "end";
    if (p.text("at", "max") != "max" && !final_) p.fail("'at' must be \"max\" or \"end\"");
  }
  void observe(const sim::Simulation&, const Tracker& t) override {
    double now = 0.0;
    for (Uid uid : uids_) {
      const int s = t.slot(uid);
      const Vec3 d = t.states()[s].position - t.initial()[s].position;
      now = std::max(now, direction_ ? std::abs(d.dot(*direction_)) : d.norm());
    }
    value_ = final_ ? now : std::max(value_, now);
  }
  double value(sim::Simulation&) override { return value_; }
  std::vector<double> state() const override { return {value_}; }
  void restore(const std::vector<double>& v) override { value_ = v.at(0); }

 private:
  std::vector<Uid> uids_;
  std::optional<Vec3> direction_;
  bool final_ = false;
  double value_ = 0.0;
};

// Max rotation angle of particles, optionally about an axis only.
class RotationCheck : public Check {
 public:
  RotationCheck(const setup::Setup& scene, const setup::CheckSpec& spec, Tracker& t) : Check(spec) {
    Params p(scene, spec);
    uids_ = p.particles(t);
    axis_ = p.vector("axis");
  }
  void observe(const sim::Simulation&, const Tracker& t) override {
    for (Uid uid : uids_) {
      const int s = t.slot(uid);
      const Quat& q0 = t.initial()[s].orientation;
      const Quat& q = t.states()[s].orientation;
      value_ = std::max(value_, axis_ ? twistAngle(q0, q, *axis_) : rotationAngle(q0, q));
    }
  }
  double value(sim::Simulation&) override { return value_; }
  std::vector<double> state() const override { return {value_}; }
  void restore(const std::vector<double>& v) override { value_ = v.at(0); }

 private:
  std::vector<Uid> uids_;
  std::optional<Vec3> axis_;
  double value_ = 0.0;
};

// Largest drift across `lateral` relative to the final travel along `direction`.
class LateralDriftCheck : public Check {
 public:
  LateralDriftCheck(const setup::Setup& scene, const setup::CheckSpec& spec, Tracker& t)
      : Check(spec) {
    Params p(scene, spec);
    uid_ = p.particles(t).front();
    direction_ = *p.vector("direction", true);
    lateral_ = *p.vector("lateral", true);
  }
  void observe(const sim::Simulation&, const Tracker& t) override {
    const int s = t.slot(uid_);
    const Vec3 d = t.states()[s].position - t.initial()[s].position;
    drift_ = std::max(drift_, std::abs(d.dot(lateral_)));
    travel_ = d.dot(direction_);
  }
  double value(sim::Simulation&) override {
    note = cat("lateral drift ", drift_, " m over a travel of ", travel_, " m");
    return travel_ > 0 ? drift_ / travel_ : kNaN;
  }
  std::vector<double> state() const override { return {drift_, travel_}; }
  void restore(const std::vector<double>& v) override {
    drift_ = v.at(0);
    travel_ = v.at(1);
  }

 private:
  Uid uid_ = 0;
  Vec3 direction_, lateral_;
  double drift_ = 0.0, travel_ = 0.0;
};

// A curve check: numerical value vs an analytical function of time; value = max error / scale.
class CurveCheck : public Check {
 public:
  using Curve = std::function<double(double)>;
  CurveCheck(const setup::CheckSpec& spec, Uid uid, Curve analytic, bool velocity, Vec3 direction,
             bool relative_to_final)
      : Check(spec),
        uid_(uid),
        analytic_(std::move(analytic)),
        velocity_(velocity),
        direction_(direction),
        relative_to_final_(relative_to_final) {}
  void observe(const sim::Simulation& sim, const Tracker& t) override {
    const int s = t.slot(uid_);
    // Positions are at t, leapfrog velocities at t - dt/2: compare each at its own time.
    const double time = velocity_ ? sim.time() - 0.5 * sim.dt() : sim.time();
    numeric_ = velocity_ ? t.states()[s].velocity.dot(direction_)
                         : (t.states()[s].position - t.initial()[s].position).dot(direction_);
    exact_ = analytic_(time);
    error_ = std::max(error_, std::abs(numeric_ - exact_));
    scale_ = relative_to_final_ ? std::abs(exact_) : std::max(scale_, std::abs(exact_));
  }
  double value(sim::Simulation&) override {
    note = cat("max |numerical - analytical| = ", error_, ", relative to ",
               relative_to_final_ ? "the final" : "the largest", " analytical value ", scale_);
    return scale_ > 0 ? error_ / scale_ : kNaN;
  }
  std::vector<std::pair<std::string, double>> seriesColumns(const sim::Simulation&) const override {
    const std::string base = columnName(spec_.name);
    return {{base, numeric_}, {base + "_analytic", exact_}};
  }
  std::vector<double> state() const override { return {numeric_, exact_, error_, scale_}; }
  void restore(const std::vector<double>& v) override {
    numeric_ = v.at(0);
    exact_ = v.at(1);
    error_ = v.at(2);
    scale_ = v.at(3);
  }

 private:
  Uid uid_;
  Curve analytic_;
  bool velocity_;
  Vec3 direction_;
  bool relative_to_final_;
  double numeric_ = 0.0, exact_ = 0.0, error_ = 0.0, scale_ = 0.0;
};

// Zhao eqs. 41-42: launched up an incline at u0, decelerated by gravity and friction, then either
// held by friction (tan(theta) <= mu) or sliding back down. s and u along `direction` (up-slope).
std::unique_ptr<Check> slidingBlock(const setup::Setup& scene, const setup::CheckSpec& spec,
                                    Tracker& t) {
  Params p(scene, spec);
  const Uid uid = p.particles(t).front();
  const double theta = degToRad(p.number("theta"));
  const double mu = p.number("mu");
  const double u0 = p.number("u0");
  const double g = p.number("g", scene.gravity.norm());
  const Vec3 dir = *p.vector("direction", true);
  const std::string quantity = p.text("quantity", "displacement");
  if (quantity != "displacement" && quantity != "velocity") {
    p.fail("'quantity' must be \"displacement\" or \"velocity\"");
  }
  const double up = g * (std::sin(theta) + mu * std::cos(theta));    // deceleration going up
  const double down = g * (std::sin(theta) - mu * std::cos(theta));  // acceleration coming down
  const double t1 = u0 / up, s0 = 0.5 * u0 * u0 / up;
  const bool slides_back = down > 0;
  CurveCheck::Curve curve;
  if (quantity == "displacement") {
    curve = [=](double time) {
      if (time <= t1) return u0 * time - 0.5 * up * time * time;
      const double tau = time - t1;
      return slides_back ? s0 - 0.5 * down * tau * tau : s0;
    };
  } else {
    curve = [=](double time) {
      if (time <= t1) return u0 - up * time;
      return slides_back ? -down * (time - t1) : 0.0;
    };
  }
  return std::make_unique<CurveCheck>(spec, uid, curve, quantity == "velocity", dir, false);
}

// Zhao eq. 45: a frictionless wedge sliding down the intersection line of two planes.
std::unique_ptr<Check> wedgeSlide(const setup::Setup& scene, const setup::CheckSpec& spec,
                                  Tracker& t) {
  Params p(scene, spec);
  const Uid uid = p.particles(t).front();
  const double theta = degToRad(p.number("theta"));
  const double g = p.number("g", scene.gravity.norm());
  const Vec3 dir = *p.vector("direction", true);  // down the intersection line
  auto curve = [=](double time) { return 0.5 * g * time * time * std::sin(theta); };
  return std::make_unique<CurveCheck>(spec, uid, curve, false, dir, true);
}

// Kinetic energy after the first contact of a particle ends, over the energy just before it began.
class EnergyRatioCheck : public Check {
 public:
  EnergyRatioCheck(const setup::Setup& scene, const setup::CheckSpec& spec, Tracker& t)
      : Check(spec) {
    uid_ = Params(scene, spec).particles(t).front();
  }
  void observe(const sim::Simulation&, const Tracker& t) override {
    const auto& s = t.states()[t.slot(uid_)];
    if (phase_ == 0 && s.contacts == 0) before_ = s.kinetic_energy;
    if (phase_ == 0 && s.contacts > 0) phase_ = 1;
    if (phase_ == 1 && s.contacts == 0) {
      after_ = s.kinetic_energy;
      phase_ = 2;
    }
  }
  double value(sim::Simulation&) override {
    if (phase_ < 2) {
      note = phase_ == 0 ? "the particle never touched anything" : "the contact never ended";
      return kNaN;
    }
    note = cat("kinetic energy ", before_, " J before contact, ", after_, " J after separation");
    return after_ / before_;
  }
  std::vector<double> state() const override { return {double(phase_), before_, after_}; }
  void restore(const std::vector<double>& v) override {
    phase_ = static_cast<int>(v.at(0));
    before_ = v.at(1);
    after_ = v.at(2);
  }

 private:
  Uid uid_ = 0;
  int phase_ = 0;  // 0 free fall, 1 in contact, 2 separated
  double before_ = 0.0, after_ = 0.0;
};

// First time a particle that was in contact has no contact left.
class SeparationCheck : public Check {
 public:
  SeparationCheck(const setup::Setup& scene, const setup::CheckSpec& spec, Tracker& t)
      : Check(spec) {
    uid_ = Params(scene, spec).particles(t).front();
  }
  void observe(const sim::Simulation& sim, const Tracker& t) override {
    const int contacts = t.states()[t.slot(uid_)].contacts;
    if (contacts > 0) touched_ = true;
    // A step's contacts are those of the positions at its start, time() - dt.
    if (touched_ && contacts == 0 && std::isnan(time_)) time_ = sim.time() - sim.dt();
  }
  double value(sim::Simulation&) override {
    if (std::isnan(time_)) note = touched_ ? "still in contact at the end" : "never in contact";
    return time_;
  }
  std::vector<double> state() const override { return {touched_ ? 1.0 : 0.0, time_}; }
  void restore(const std::vector<double>& v) override {
    touched_ = v.at(0) != 0.0;
    time_ = v.at(1);
  }

 private:
  Uid uid_ = 0;
  bool touched_ = false;
  double time_ = kNaN;
};

// Values read at the end of the run.
class FinalCheck : public Check {
 public:
  FinalCheck(const setup::CheckSpec& spec, std::function<double(sim::Simulation&, std::string&)> f)
      : Check(spec), f_(std::move(f)) {}
  void observe(const sim::Simulation&, const Tracker&) override {}
  double value(sim::Simulation& sim) override { return f_(sim, note); }

 private:
  std::function<double(sim::Simulation&, std::string&)> f_;
};

double equilibriumSteps(sim::Simulation& sim, std::string& note) {
  if (!sim.scene().equilibrium.enabled) {
    note = "the scene has no [equilibrium] stage";
    return kNaN;
  }
  if (!sim.equilibriumReached()) {
    note = cat("R < ", sim.scene().equilibrium.force_ratio, " not reached within ",
               sim.equilibriumSteps(), " steps");
    return kNaN;
  }
  return static_cast<double>(sim.equilibriumSteps());
}

double maxContactForce(sim::Simulation& sim, const std::optional<Vec3>& axis, std::string& note) {
  const Vec3 down = axis ? *axis : sim.scene().gravity.normalized();
  double largest = 0.0, weight = 0.0;
  std::int64_t free_particles = 0;
  const auto& storage = sim.particles();
  for (std::size_t i = 0; i < storage.localCount(); ++i) {
    if (!storage[i].isFree()) continue;
    weight += sim.massProperties(i).mass * sim.scene().gravity.norm();
    ++free_particles;
  }
  for (const auto& r : sim.contacts().records()) {
    if (!r.touching || !r.both_free) continue;  // between two free particles
    largest = std::max(largest, (r.force - r.force.dot(down) * down).norm());
  }
  // A pair across two ranks is evaluated on both with equal results: the max is unaffected.
  largest = mpi::allreduceMax(largest, sim.comm());
  ExactSum w;
  w += weight;
  w.allreduce(sim.comm());
  const auto n = mpi::allreduceSum(free_particles, sim.comm());
  const double mean_weight = n > 0 ? w.value() / static_cast<double>(n) : kNaN;
  note =
      cat("largest contact force across the axis ", largest, " N; mean weight ", mean_weight, " N");
  return largest / mean_weight;
}

}  // namespace

Uid uidOfLabel(const setup::Setup& scene, const std::string& label) {
  for (const auto& p : scene.particles) {
    if (p.label == label) return p.uid;
  }
  return 0;
}

namespace {

struct KindEntry {
  std::string kind;
  CheckFactory make;
};

// A kind of check whose whole value is read from the simulation at the end.
CheckFactory atTheEnd(std::function<double(sim::Simulation&, std::string&)> value) {
  return [value](const setup::Setup&, const setup::CheckSpec& spec,
                 Tracker&) -> std::unique_ptr<Check> {
    return std::make_unique<FinalCheck>(spec, value);
  };
}

template <typename C>
CheckFactory tracked() {
  return [](const setup::Setup& scene, const setup::CheckSpec& spec,
            Tracker& t) -> std::unique_ptr<Check> { return std::make_unique<C>(scene, spec, t); };
}

// The built-in kinds, in the order of docs/scene-format.md; then those registered by programs.
std::vector<KindEntry>& registry() {
  static std::vector<KindEntry> kinds = {
      {"displacement", tracked<DisplacementCheck>()},
      {"rotation", tracked<RotationCheck>()},
      {"lateral_drift", tracked<LateralDriftCheck>()},
      {"sliding_block", slidingBlock},
      {"wedge_slide", wedgeSlide},
      {"kinetic_energy_ratio", tracked<EnergyRatioCheck>()},
      {"separation_time", tracked<SeparationCheck>()},
      {"equilibrium_steps", atTheEnd(equilibriumSteps)},
      {"mean_speed",
       atTheEnd([](sim::Simulation& sim, std::string&) { return sim.monitors().mean_speed; })},
      {"max_speed",
       atTheEnd([](sim::Simulation& sim, std::string&) { return sim.monitors().max_speed; })},
      // Touching pairs at the end, each once: cubes pushing their neighbours make new contacts.
      {"contact_count", atTheEnd([](sim::Simulation& sim, std::string&) {
         return static_cast<double>(sim.monitors().contacts);
       })},
      {"max_contact_force",
       [](const setup::Setup& scene, const setup::CheckSpec& spec,
          Tracker&) -> std::unique_ptr<Check> {
         const auto axis = Params(scene, spec).vector("axis");
         return std::make_unique<FinalCheck>(spec, [axis](sim::Simulation& sim, std::string& note) {
           return maxContactForce(sim, axis, note);
         });
       }},
      {"free_motion", makeMotionCheck},
      {"tilt_failure", makeMotionCheck},
      {"pair_separation", makeMotionCheck},
  };
  return kinds;
}

}  // namespace

void registerCheckKind(std::string kind, CheckFactory factory) {
  if (kind.empty()) throw Error("registerCheckKind: a check kind needs a name");
  if (!factory) throw Error(cat("registerCheckKind: check kind '", kind, "' has no factory"));
  if (findCheckFactory(kind)) {
    throw Error(cat("registerCheckKind: check kind '", kind, "' is already registered"));
  }
  registry().push_back({std::move(kind), std::move(factory)});
}

const CheckFactory* findCheckFactory(std::string_view kind) {
  for (const auto& k : registry()) {
    if (k.kind == kind) return &k.make;
  }
  return nullptr;
}

std::vector<std::string> registeredCheckKinds() {
  std::vector<std::string> kinds;
  for (const auto& k : registry()) kinds.push_back(k.kind);
  return kinds;
}

std::vector<std::unique_ptr<Check>> makeChecks(const setup::Setup& scene, Tracker& tracker) {
  std::vector<std::unique_ptr<Check>> checks;
  for (const auto& spec : scene.checks) {
    const CheckFactory* make = findCheckFactory(spec.kind);
    if (!make) Params(scene, spec).fail("unknown kind; known kinds: " + scene::checkKindNames());
    auto check = (*make)(scene, spec, tracker);
    if (!check) {
      throw Error(cat("check kind '", spec.kind, "' built no check for '", spec.name, "'"));
    }
    checks.push_back(std::move(check));
  }
  return checks;
}

std::vector<output::CheckResult> evaluateChecks(std::vector<std::unique_ptr<Check>>& checks,
                                                sim::Simulation& sim) {
  std::vector<output::CheckResult> results;
  for (auto& c : checks) {
    const auto& s = c->spec();
    output::CheckResult r;
    r.name = s.name;
    r.kind = s.kind;
    r.value = c->value(sim);
    if (const scene::CheckKind* kind = scene::findCheckKind(s.kind)) {
      r.unit = scene::storedUnit(scene::valueQuantity(*kind, s));
    }
    r.expected = s.expected;
    r.tolerance = s.tolerance;
    r.compare = s.compare;
    r.reference = s.reference;
    r.note = c->note;
    r.pass = output::checkPasses(s.compare, r.value, s.expected, s.tolerance);
    results.push_back(r);
  }
  return results;
}

}  // namespace polydem::run
