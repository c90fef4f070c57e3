// The physics of face contacts with sub-contacts, run as whole simulations with every penalty
// kernel: a rocking cube conserves energy, a spinning cube is stopped by friction, a block stays
// below its friction angle and slides with Coulomb's acceleration above it, a tilting platform
// lets a block slip at the rigid answer's angle. The single-point model fails the first three
// (docs/dynamics.md): the tests that say so are the same tests run with contact_model = "point".
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>
#include <string>

#include "polydem/core/logging.h"
#include "polydem/core/strings.h"
#include "polydem/dynamics/monitors.h"
#include "polydem/scene/scene_reader.h"
#include "polydem/sim/simulation.h"

namespace polydem::sim {
namespace {

constexpr double kG = 9.81, kDensity = 2500.0, kKn = 1e8, kKs = 5e7, kDt = 1e-4;
constexpr double kPi = std::numbers::pi;

double deg(double d) {
  return d * kPi / 180.0;
}

struct CubeScene {
  std::string kernel = "gjk-epa-ipm";
  std::string model = "sub-contacts";
  double friction_deg = 0.0;
  double slope_deg = 0.0;  // gravity tilted about y: the plate is an incline dipping along +x
  Vec3 angular_velocity = Vec3::Zero();
  Vec3 velocity = Vec3::Zero();
  double end_time = 1.0;
  std::string extra;  // more TOML (drivers)
  std::string plate = "fixed = true";
};

// A 1 m cube resting at its static penetration on a 6 x 6 x 1 m plate.
std::string toml(const CubeScene& c) {
  const double g = kG;
  const double gx = g * std::sin(deg(c.slope_deg)), gz = -g * std::cos(deg(c.slope_deg));
  const double penetration = kDensity * g * std::cos(deg(c.slope_deg)) / kKn;
  return cat(R"([scene]
id = "face-contact-physics"
[simulation]
kernel = ")",
             c.kernel, R"("
contact_model = ")",
             c.model, R"("
dt = )",
             kDt, "\nend_time = ", c.end_time, "\ngravity = [", gx, ", 0, ", gz, R"(]
[domain]
min = [-8, -8, -4]
max = [8, 8, 6]
[[material]]
name = "rock"
density = )",
             kDensity, "\nkn = ", kKn, "\nks = ", kKs, "\npenalty = ", kKn,
             "\nfriction_angle = ", c.friction_deg, R"(
[[shape]]
name = "cube"
type = "box"
size = [1, 1, 1]
[[shape]]
name = "plate"
type = "box"
size = [6, 6, 1]
[[particle]]
label = "plate"
shape = "plate"
material = "rock"
position = [0, 0, -0.5]
)",
             c.plate, R"(
[[particle]]
label = "cube"
shape = "cube"
material = "rock"
position = [0, 0, )",
             0.5 - penetration, "]\nvelocity = [", c.velocity.x(), ", ", c.velocity.y(), ", ",
             c.velocity.z(), "]\nangular_velocity = [", c.angular_velocity.x(), ", ",
             c.angular_velocity.y(), ", ", c.angular_velocity.z(), "]\n", c.extra);
}

// The free cube's entry in the storage (one rank).
std::size_t cubeIndex(const Simulation& sim) {
  const auto& s = sim.particles();
  for (std::size_t i = 0; i < s.localCount(); ++i) {
    if (s[i].isFree()) return i;
  }
  ADD_FAILURE() << "no free particle";
  return 0;
}

// Runs the scene, calling `observe(sim, cube index)` after every step.
void run(const CubeScene& c, const std::function<void(const Simulation&, std::size_t)>& observe) {
  log::setLevel(log::Level::kWarning);
  Simulation sim(scene::parseScene(toml(c), "<face-contact-physics>"), MPI_COMM_WORLD);
  const auto steps = static_cast<std::int64_t>(std::llround(c.end_time / kDt));
  for (std::int64_t k = 0; k < steps; ++k) {
    sim.step();
    observe(sim, cubeIndex(sim));
  }
}

class FaceContactPhysics : public ::testing::TestWithParam<const char*> {};

// A frictionless, undamped cube rocking on a plate about an oblique axis: kinetic + gravitational
// + spring energy stays what it was over 10 s (the single-point model gains 30-300x).
TEST_P(FaceContactPhysics, RockingCubeConservesEnergy) {
  for (const double initial : {0.07, 0.7}) {  // J of rocking energy
    CubeScene c;
    c.kernel = GetParam();
    c.end_time = 10.0;
    const double inertia = kDensity / 6.0;  // unit cube about any axis through the centroid
    c.angular_velocity = std::sqrt(2.0 * initial / inertia) * Vec3(1, 0.5, 0).normalized();
    double e0 = 0.0, worst = 0.0, z_max = 0.0;
    bool first = true;
    run(c, [&](const Simulation& sim, std::size_t i) {
      const auto& s = sim.particles();
      double e =
          dynamics::kineticEnergy(s[i], sim.massProperties(i)) + s.mass(i) * kG * s[i].position.z();
      for (const auto& r : sim.contacts().records()) e += r.energy;
      if (first) e0 = e, first = false;
      worst = std::max(worst, std::abs(e - e0));
      z_max = std::max(z_max, s[i].position.z());
    });
    EXPECT_LT(worst, 0.02 * initial) << GetParam() << ", rocking energy " << initial << " J";
    EXPECT_LT(z_max, 0.5) << "the cube left the plate";
  }
}

// The same with 30 deg friction and a push along x small enough that no corner slips: the shear
// springs are elastic too, and the total energy (with theirs) stays what it was.
TEST_P(FaceContactPhysics, StickingCubeConservesEnergy) {
  CubeScene c;
  c.kernel = GetParam();
  c.friction_deg = 30.0;
  c.end_time = 4.0;
  c.angular_velocity = Vec3(0.0, 0.01, 0.0);
  double e0 = 0.0, worst = 0.0, e_first = 0.0;
  int step = 0;
  run(c, [&](const Simulation& sim, std::size_t i) {
    const auto& s = sim.particles();
    double e =
        dynamics::kineticEnergy(s[i], sim.massProperties(i)) + s.mass(i) * kG * s[i].position.z();
    for (const auto& r : sim.contacts().records()) e += r.energy;
    if (step == 0) e0 = e, e_first = dynamics::kineticEnergy(s[i], sim.massProperties(i));
    worst = std::max(worst, std::abs(e - e0));
    ++step;
  });
  EXPECT_LT(worst, 0.02 * e_first) << GetParam();
}

// A cube spinning at 1 rad/s about the normal with 30 deg friction: the corner springs slip at
// mu m g / 4 each, a lever of sqrt(2)/2 m, so it stops after turning w0^2 / (2 alpha),
// alpha = 6 mu g sqrt(2)/2 / a^2 (the single-point model never stops it). It then stays.
TEST_P(FaceContactPhysics, SpinningCubeStops) {
  CubeScene c;
  c.kernel = GetParam();
  c.friction_deg = 30.0;
  c.angular_velocity = Vec3(0, 0, 1.0);
  c.end_time = 1.0;
  double angle_at = 0.0, angle_end = 0.0;
  int step = 0;
  run(c, [&](const Simulation& sim, std::size_t i) {
    const Quat& q = sim.particles()[i].orientation;
    const double angle = 2.0 * std::atan2(q.z(), q.w());
    if (++step == 2000) angle_at = angle;
    angle_end = angle;
  });
  const double alpha = 6.0 * std::tan(deg(30)) * kG * std::sqrt(0.5);
  EXPECT_NEAR(angle_at, 1.0 / (2.0 * alpha), 0.05 / (2.0 * alpha)) << "stopping angle";
  EXPECT_LT(std::abs(angle_end - angle_at), 1e-3) << "turned on after stopping";
}

// Below the friction angle (26 deg against 30), released at rest: the unloaded shear springs let
// it slide about a millimetre while they take the load (undamped: the first swing overshoots the
// Coulomb limit), then it stays; its mean position does not move (the single-point model slides
// off the plate).
TEST_P(FaceContactPhysics, BlockBelowTheFrictionAngleStays) {
  CubeScene c;
  c.kernel = GetParam();
  c.friction_deg = 30.0;
  c.slope_deg = 26.0;
  c.end_time = 2.0;
  double early = 0.0, late = 0.0, largest = 0.0;
  int step = 0;
  run(c, [&](const Simulation& sim, std::size_t i) {
    const double x = sim.particles()[i].position.x();
    ++step;
    if (step > 2000 && step <= 10000) early += x / 8000.0;  // mean over 0.2 - 1 s
    if (step > 12000) late += x / 8000.0;                   // over 1.2 - 2 s
    largest = std::max(largest, std::abs(x));
  });
  EXPECT_LT(largest, 3e-3) << "slid on being put down";
  EXPECT_LT(std::abs(late - early), 5e-6)
      << "creeps: mean position " << early << " m, then " << late << " m";
}

// Above it (40 deg against 30, and 30 against 20): Coulomb's acceleration g (sin theta -
// mu cos theta) within 2 %, from the velocities at 0.5 s and 1 s (after the shear springs have
// loaded).
TEST_P(FaceContactPhysics, BlockAboveTheFrictionAngleSlidesAsCoulombSays) {
  for (const auto& [slope, friction] : {std::pair{40.0, 30.0}, std::pair{30.0, 20.0}}) {
    CubeScene c;
    c.kernel = GetParam();
    c.friction_deg = friction;
    c.slope_deg = slope;
    c.end_time = 1.0;
    double v_half = 0.0, v_end = 0.0;
    int step = 0;
    run(c, [&](const Simulation& sim, std::size_t i) {
      v_end = sim.particles()[i].velocity.x();
      if (++step == 5000) v_half = v_end;
    });
    const double a = kG * (std::sin(deg(slope)) - std::tan(deg(friction)) * std::cos(deg(slope)));
    EXPECT_NEAR((v_end - v_half) / 0.5 / a, 1.0, 0.02)
        << slope << " deg slope, " << friction << " deg friction";
  }
}

// The rigid answer for a platform tilting at `rate` from flat: the slope when the block has slid
// `slip` relative to it, from s'' = g (sin(rate t) - mu cos(rate t)) once rate t > phi.
double rigidSlipAngle(double friction_deg, double rate, double slip) {
  const double mu = std::tan(deg(friction_deg)), h = 1e-6;
  double t = deg(friction_deg) / rate, s = 0.0, v = 0.0;
  while (s < slip) {
    v += h * kG * (std::sin(rate * t) - mu * std::cos(rate * t));
    s += h * v;
    t += h;
  }
  return rate * t * 180.0 / kPi;
}

// A platform tilting at 0.2 rad/s about a hinge under the block: the block has slid 5 mm relative
// to it at the rigid answer's angle (32.7 deg for 30 deg friction; the elastic stretch of the
// shear springs, 0.3 mm, shifts it by 0.06 deg), not at half of it as with the single point.
TEST_P(FaceContactPhysics, TiltTableSlipAngle) {
  CubeScene c;
  c.kernel = GetParam();
  c.friction_deg = 30.0;
  const double rate = 0.2;
  c.end_time = 3.0;
  c.plate = "driver = \"tilt\"";
  // The cube starts turning with the platform (no jolt): w = (0, -rate, 0), v = w x (0, 0, 1/2).
  c.angular_velocity = Vec3(0, -rate, 0);
  c.velocity = Vec3(-0.5 * rate, 0, 0);
  c.extra = cat("[[driver]]\nname = \"tilt\"\nangular_velocity = [0, ", -rate,
                ", 0]\npivot = [0, 0, 0]\n");
  double slip_angle = -1.0;
  const Vec3 start(0, 0, 0.5);
  run(c, [&](const Simulation& sim, std::size_t i) {
    if (slip_angle >= 0.0) return;
    const double theta = rate * sim.time();  // turning about -y lifts +x: the block slides to -x
    const Mat3 r = Eigen::AngleAxisd(theta, -Vec3::UnitY()).toRotationMatrix();
    const Vec3 relative = r.transpose() * sim.particles()[i].position - start;
    if (relative.norm() > 5e-3) slip_angle = theta * 180.0 / kPi;
  });
  const double rigid = rigidSlipAngle(30.0, rate, 5e-3);
  EXPECT_NEAR(slip_angle, rigid, 0.3) << "rigid answer " << rigid << " deg";
}

INSTANTIATE_TEST_SUITE_P(PenaltyKernels, FaceContactPhysics,
                         ::testing::Values("gjk-epa", "gjk-epa-ipm", "fcp", "fcp-ipm", "lp"),
                         [](const auto& param_info) {
                           std::string name = param_info.param;
                           for (char& ch : name) ch = ch == '-' ? '_' : ch;
                           return name;
                         });

}  // namespace
}  // namespace polydem::sim
