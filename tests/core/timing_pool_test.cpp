#include "polydem/core/timing_pool.h"

#include <gtest/gtest.h>

#include "polydem/core/mpi_env.h"

namespace polydem {
namespace {

TEST(TimingPool, AccumulatesAndReducesOverRanks) {
  TimingPool pool;
  pool.add("contact", 1.0 + mpi::rank());
  pool.add("contact", 1.0);
  if (mpi::rank() == 0) pool.add("only-on-rank-0", 0.5);
  { auto s = pool.scope("scoped"); }
  EXPECT_EQ(pool.entries()[0].count, 2);
  EXPECT_DOUBLE_EQ(pool.seconds("contact"), 2.0 + mpi::rank());

  const auto rows = pool.reduce(MPI_COMM_WORLD);
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0].name, "contact");
  const int n = mpi::size();
  EXPECT_DOUBLE_EQ(rows[0].min, 2.0);
  EXPECT_DOUBLE_EQ(rows[0].max, 2.0 + (n - 1));
  EXPECT_DOUBLE_EQ(rows[0].mean, 2.0 + (n - 1) / 2.0);
  EXPECT_NE(TimingPool::table(rows, 10).find("only-on-rank-0"), std::string::npos);
}

// The running total is what a timer that times parts of itself into the pool deducts.
TEST(TimingPool, TotalSecondsSumsEveryCallAndClears) {
  TimingPool pool;
  EXPECT_EQ(pool.totalSeconds(), 0.0);
  pool.add("a", 1.5);
  pool.add("b", 0.25);
  pool.add("a", 2.0);
  EXPECT_EQ(pool.totalSeconds(), 3.75);
  EXPECT_EQ(pool.totalSeconds(), pool.seconds("a") + pool.seconds("b"));
  pool.clear();
  EXPECT_EQ(pool.totalSeconds(), 0.0);
}

}  // namespace
}  // namespace polydem
