#include "polydem/core/strings.h"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace polydem
