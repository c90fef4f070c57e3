// [[random]] entries and the realizations drawn from them (scene/scene_random.h), and Fisher's
// distribution of joint-set poles (core/random.h fisherAngle, geometry/joint_planes.h).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "polydem/core/error.h"
#include "polydem/core/random.h"
#include "polydem/geometry/joint_planes.h"
#include "polydem/scene/scene_random.h"

namespace polydem::scene {
namespace {

const std::string kScene = R"([scene]
id = "T"

[simulation]
dt = "1e-4 s"
end_time = "1 s"

[[material]]
name = "rock"
density = 2600
kn = 1e9
friction_angle = 30

[[joint]]
name = "bedding"
jkn = "1 GPa/m"
jks = "0.5 GPa/m"
friction_angle = 30
cohesion = "5 kPa"

[[rock_mass]]
name = "slope"
material = "rock"
region = { type = "box", min = [0, 0, 0], max = [4, 4, 4] }

[[rock_mass.joint_set]]
name = "J1"
dip = 40
dip_direction = 90
spacing = "1.5 m"
fisher_k = 30
joint = "bedding"

[realizations]
seed = 11
)";

std::string writeScene(const std::string& name, const std::string& random) {
  const auto path = std::filesystem::temp_directory_path() / ("scene_random_" + name + ".toml");
  std::ofstream(path) << kScene << random;
  return path.string();
}

const std::string kInputs = R"(
[[random]]
parameter = "joint.bedding.friction_angle"
distribution = "normal"
mean = 32
sd = 3

[[random]]
parameter = "joint.bedding.cohesion"
distribution = "lognormal"
mean = 5000
sd = 2000

[[random]]
parameter = "material.rock.friction_angle"
distribution = "truncated"
mean = 30
sd = 5
min = 28
max = 40

[[random]]
parameter = "rock_mass.slope.joint_set.J1.spacing"
distribution = "uniform"
min = 1.2
max = 1.8

[[random]]
parameter = "rock_mass.slope.joint_set.J1"
distribution = "fisher"
k = 50
)";

TEST(NormalQuantile, InvertsTheCdfToRoundOff) {
  for (const double p : {1e-12, 1e-5, 0.01, 0.0243, 0.2, 0.5, 0.7, 0.975, 0.9999}) {
    EXPECT_NEAR(normalCdf(normalQuantile(p)), p, 4e-16 + 1e-14 * p) << p;
  }
  EXPECT_NEAR(normalQuantile(0.975), 1.959963984540054, 1e-14);
  EXPECT_THROW(normalQuantile(0.0), Error);
}

// The exact inversion: its mean of cos(theta) over evenly spaced u is E[cos theta] =
// coth(K) - 1/K, Fisher's mean resultant length, to the quadrature's accuracy.
TEST(FisherAngle, HasFishersMeanResultantLength) {
  for (const double k : {0.5, 5.0, 50.0, 500.0}) {
    const int n = 200000;
    double sum = 0.0;
    for (int i = 0; i < n; ++i) sum += std::cos(fisherAngle(k, (i + 0.5) / n));
    EXPECT_NEAR(sum / n, 1.0 / std::tanh(k) - 1.0 / k, 1e-6) << "K = " << k;
  }
  EXPECT_EQ(fisherAngle(10.0, 0.0), 0.0);
}

// A joint set's planes with Fisher scatter: every normal on the set's side, their mean cos with
// the set's pole Fisher's (within 4 standard errors of the mean).
TEST(FisherAngle, ScattersJointSetPlanes) {
  geometry::JointSet set;
  set.name = "J";
  set.dip = 40;
  set.dip_direction = 90;
  set.spacing = 0.01;
  set.fisher_k = 20;
  set.seed = 3;
  const std::vector<Vec3> box = {Vec3(0, 0, 0), Vec3(10, 0, 0), Vec3(0, 10, 0), Vec3(0, 0, 10),
                                 Vec3(10, 10, 10)};
  const auto planes = geometry::jointSetPlanes(set, box);
  ASSERT_GT(planes.size(), 1000u);
  const Vec3 n0 = geometry::normalFromDip(set.dip, set.dip_direction);
  double sum = 0.0, squares = 0.0;
  for (const auto& p : planes) {
    const double c = p.plane.normal.dot(n0);
    EXPECT_GE(c, 0.0);
    sum += c;
    squares += c * c;
  }
  const double n = static_cast<double>(planes.size()), mean = sum / n;
  const double se = std::sqrt((squares / n - mean * mean) / n);
  // Folding the poles beyond 90 deg changes the mean by exp(-2K)-small amounts only.
  EXPECT_NEAR(mean, 1.0 / std::tanh(set.fisher_k) - 1.0 / set.fisher_k, 4.0 * se);
  set.orientation_jitter = 5;
  EXPECT_THROW(geometry::jointSetPlanes(set, box), GeometryError);
}

TEST(Realizations, AreDeterministicAndFollowTheirDistributions) {
  const Study study = readStudy(writeScene("draws", kInputs));
  ASSERT_EQ(study.inputs.size(), 5u);
  EXPECT_EQ(study.seed, 11u);
  ASSERT_EQ(study.columns().size(), 6u);  // fisher: dip and dip_direction
  const Realization a = drawRealization(study, 7), b = drawRealization(study, 7);
  EXPECT_EQ(a.text, b.text);
  EXPECT_EQ(a.values, b.values);
  EXPECT_NE(drawRealization(study, 8).values, a.values);
  // The scene of a realization holds its draws.
  const setup::Setup scene = realizationScene(study, a);
  EXPECT_EQ(scene.materials[0].friction_angle, a.values[2]);

  const int n = 1500;
  std::vector<double> sum(6, 0.0), squares(6, 0.0);
  for (int i = 0; i < n; ++i) {
    const Realization r = drawRealization(study, i);
    for (std::size_t k = 0; k < 6; ++k) {
      sum[k] += r.values[k];
      squares[k] += r.values[k] * r.values[k];
    }
    EXPECT_GE(r.values[2], 28.0);
    EXPECT_LE(r.values[2], 40.0);
    EXPECT_GE(r.values[3], 1.2);
    EXPECT_LT(r.values[3], 1.8);
    EXPECT_GT(r.values[1], 0.0);
    EXPECT_GE(r.values[4], 0.0);
    EXPECT_LE(r.values[4], 90.0);
  }
  const auto mean = [&](int k) { return sum[k] / n; };
  const auto sd = [&](int k) { return std::sqrt(squares[k] / n - mean(k) * mean(k)); };
  // Normal and lognormal: the mean within 4 standard errors, the sd within 10 %.
  EXPECT_NEAR(mean(0), 32.0, 4.0 * 3.0 / std::sqrt(n));
  EXPECT_NEAR(sd(0), 3.0, 0.3);
  EXPECT_NEAR(mean(1), 5000.0, 4.0 * 2000.0 / std::sqrt(n));
  EXPECT_NEAR(sd(1), 2000.0, 200.0);
  EXPECT_NEAR(mean(3), 1.5, 4.0 * 0.6 / std::sqrt(12.0 * n));
  // Truncated normal on [28, 40] about 30 (sd 5): its mean by quadrature of the density.
  double w = 0.0, wx = 0.0;
  for (int i = 0; i < 120000; ++i) {
    const double x = 28.0 + 12.0 * (i + 0.5) / 120000;
    const double f = std::exp(-0.5 * ((x - 30.0) / 5.0) * ((x - 30.0) / 5.0));
    w += f;
    wx += f * x;
  }
  EXPECT_NEAR(mean(2), wx / w, 4.0 * 3.4 / std::sqrt(n));
}

TEST(Realizations, EachHasItsOwnJointSetSeed) {
  const Study study = readStudy(writeScene("seeds", kInputs));
  const std::string a = drawRealization(study, 0).text, b = drawRealization(study, 1).text;
  const auto seedOf = [](const std::string& text) {
    const auto at = text.find("seed = ");
    return text.substr(at, text.find('\n', at) - at);
  };
  EXPECT_NE(seedOf(a), seedOf(b));
}

// Bad entries: InputError at the entry's line.
TEST(Realizations, RefuseBadEntries) {
  const auto refused = [](const std::string& name, const std::string& entry,
                          const std::string& message) {
    const std::string path = writeScene(name, entry);
    try {
      readStudy(path);
      ADD_FAILURE() << name << ": accepted";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(path + ":"), std::string::npos) << what;
      EXPECT_NE(what.find(message), std::string::npos) << what;
    }
  };
  refused("none", "", "no [[random]] entry");
  refused("distribution",
          "[[random]]\nparameter = \"joint.bedding.friction_angle\"\ndistribution = \"beta\"\n",
          "beta");
  refused("fisher_on_number",
          "[[random]]\nparameter = \"joint.bedding.friction_angle\"\ndistribution = "
          "\"fisher\"\nk = 10\n",
          "not a table");
  refused("twice",
          "[[random]]\nparameter = \"joint.bedding.cohesion\"\ndistribution = \"uniform\"\nmin = "
          "0\nmax = 1\n[[random]]\nparameter = \"joint.bedding.cohesion\"\ndistribution = "
          "\"uniform\"\nmin = 0\nmax = 2\n",
          "already drawn at line");
  refused("no_table",
          "[[random]]\nparameter = \"seismic.kh\"\ndistribution = \"uniform\"\nmin = 0\nmax = "
          "0.1\n",
          "the scene has no 'seismic'");
  refused("bad_key",
          "[[random]]\nparameter = \"joint.bedding.friction\"\ndistribution = "
          "\"uniform\"\nmin = 20\nmax = 30\n",
          "unknown key 'friction'");
  refused("min_max",
          "[[random]]\nparameter = \"joint.bedding.friction_angle\"\ndistribution = "
          "\"uniform\"\nmin = 30\nmax = 30\n",
          "must exceed min");
  refused("extra_key",
          "[[random]]\nparameter = \"joint.bedding.friction_angle\"\ndistribution = "
          "\"normal\"\nmean = 30\nsd = 2\nmin = 1\n",
          "not a parameter of the normal distribution");
}

}  // namespace
}  // namespace polydem::scene
