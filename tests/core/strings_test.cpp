#include "polydem/core/strings.h"

#include <gtest/gtest.h>

#include <cfloat>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <random>

namespace polydem {
namespace {

TEST(Strings, SplitKeepsTheNonEmptyItemsInOrder) {
  EXPECT_EQ(split("lp,fcp-ipm,gjk-epa", ','),
            (std::vector<std::string>{"lp", "fcp-ipm", "gjk-epa"}));
  EXPECT_EQ(split(",a,,b,", ','), (std::vector<std::string>{"a", "b"}));
  EXPECT_TRUE(split("", ',').empty());
  EXPECT_EQ(split("a b", ','), (std::vector<std::string>{"a b"}));
}

TEST(Strings, JoinUndoesSplit) {
  const std::vector<std::string> parts{"x", "y", "z"};
  EXPECT_EQ(split(join(parts, ","), ','), parts);
}

TEST(Strings, CatPrintsTheDigitsThatMatter) {
  EXPECT_EQ(cat("phi = ", 0.8), "phi = 0.8");
  EXPECT_EQ(cat(0.1 + 0.2), "0.30000000000000004");  // not 0.3: that would be another double
  EXPECT_EQ(cat(1e-5, " ", 2.0, " ", -0.0, " ", 1.5e300), "1e-05 2 -0 1.5e+300");
  EXPECT_EQ(cat(1e15, " ", 1e17, " ", 1e-4, " ", 123456.7),
            "1000000000000000 1e+17 0.0001 123456.7");
  EXPECT_EQ(cat(0.1f), "0.1");  // a float by its own shortest digits, not its double's
  EXPECT_EQ(cat(42, " ", std::string("m")), "42 m");
}

TEST(Strings, ShortestReadsBackAsTheSameDouble) {
  std::mt19937_64 random(7);
  std::vector<double> values = {DBL_MAX,   DBL_MIN,   4.9406564584124654e-324,
                                1.0 / 3.0, 2.0 / 3.0, 9007199254740993.0,
                                0.8,       1e23};
  for (int i = 0; i < 10000; ++i) {
    std::uint64_t bits = random();
    double x = 0.0;
    std::memcpy(&x, &bits, sizeof x);
    if (x == x && x - x == 0.0) values.push_back(x);  // finite
  }
  for (const double x : values) {
    const std::string text = shortest(x);
    const double back = std::strtod(text.c_str(), nullptr);
    EXPECT_EQ(std::memcmp(&back, &x, sizeof x), 0) << text;
    EXPECT_LE(text.size(), 24u) << text;  // 17 digits, sign, point and a 5-character exponent
  }
}

}  // namespace
}  // namespace polydem
