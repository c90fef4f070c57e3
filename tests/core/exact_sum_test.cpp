#include "polydem/core/exact_sum.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "polydem/core/mpi_env.h"

namespace polydem {
namespace {

TEST(ExactSum, CancellationThatDefeatsNaiveSumming) {
  ExactSum s;
  s += 1e20;
  s += 1.0;
  s += -1e20;
  EXPECT_EQ(s.value(), 1.0);  // naive left-to-right summing gives 0
}

TEST(ExactSum, SameBitsInAnyOrder) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> mant(-1.0, 1.0);
  std::uniform_int_distribution<int> expo(-40, 40);
  std::vector<double> values(20000);
  for (auto& v : values) v = std::ldexp(mant(rng), expo(rng));
  const double reference = exactSum(values);
  for (int shuffle = 0; shuffle < 5; ++shuffle) {
    std::shuffle(values.begin(), values.end(), rng);
    EXPECT_EQ(exactSum(values), reference);
  }
  // and within rounding of a long-double Kahan sum of the same numbers
  long double kahan = 0, c = 0;
  for (double v : values) {
    long double y = v - c, t = kahan + y;
    c = (t - kahan) - y;
    kahan = t;
  }
  EXPECT_NEAR(reference, static_cast<double>(kahan), 1e-12 * std::abs(reference) + 1e-300);
}

TEST(ExactSum, NegativeTotalsSubnormalsAndNaN) {
  ExactSum s;
  s += -3.5;
  s += 1.25;
  EXPECT_EQ(s.value(), -2.25);
  ExactSum tiny;
  tiny += 4.9e-324;
  tiny += 4.9e-324;
  EXPECT_EQ(tiny.value(), 2 * 4.9e-324);
  ExactSum bad;
  bad += 1.0;
  bad += std::nan("");
  EXPECT_TRUE(std::isnan(bad.value()));
}

TEST(ExactSum, ManyAdditionsTriggerCarryPropagation) {
  ExactSum s;
  const int n = (1 << 20) + 7;
  for (int i = 0; i < n; ++i) s += 0.1;
  // 0.1 is not exact in binary; the exact sum of n copies of fl(0.1), rounded once:
  EXPECT_EQ(s.value(), static_cast<double>(static_cast<long double>(0.1) * n));
}

TEST(ExactSum, AllreduceIsIndependentOfRankCount) {
  // Every rank adds a different slice of the same 1000 numbers; the reduced sum must equal the
  // sum made on one rank with no MPI at all.
  const int rank = mpi::rank(), size = mpi::size();
  std::vector<double> values(1000);
  for (int i = 0; i < 1000; ++i) values[i] = std::sin(i * 1.7) * std::pow(10.0, i % 13 - 6);
  ExactSum part;
  for (int i = rank; i < 1000; i += size) part += values[i];
  part.allreduce(MPI_COMM_WORLD);
  EXPECT_EQ(part.value(), exactSum(values));
}

}  // namespace
}  // namespace polydem
