// The sub-commands' argument parser (apps/polydem/args.cpp): numbers and whole numbers are taken
// only when the whole word is one, in range; anything else is a UsageError naming the option.
#include <gtest/gtest.h>

#include <initializer_list>
#include <string>
#include <vector>

#include "commands.h"

namespace polydem::app {
namespace {

// Args over "--name value", as a command line gives them.
Args argsOf(const std::string& name, const std::string& value) {
  static std::vector<std::string> words;
  words = {"--" + name, value};
  static std::vector<char*> argv;
  argv = {words[0].data(), words[1].data()};
  return Args(2, argv.data());
}

// The UsageError's message, or "" if the call was taken.
template <typename F>
std::string refusal(F call) {
  try {
    call();
  } catch (const UsageError& e) {
    return e.what();
  }
  return "";
}

std::string integerRefusal(const std::string& value, long long min = 0,
                           long long max = Args::kInt64Max) {
  return refusal([&] { argsOf("steps", value).integer("steps", 0, min, max); });
}

std::string numberRefusal(const std::string& value, double min = Args::kLowest) {
  return refusal([&] { argsOf("end-time", value).number("end-time", 0.0, min); });
}

TEST(Args, WholeNumbers) {
  EXPECT_EQ(argsOf("steps", "12").integer("steps", 0, 1), 12);
  EXPECT_EQ(argsOf("steps", "+12").integer("steps", 0, 1), 12);
  EXPECT_EQ(argsOf("steps", "-12").integer("steps", 0, -20), -12);
  EXPECT_EQ(argsOf("steps", "9223372036854775807").integer("steps", 0, 1, Args::kInt64Max),
            Args::kInt64Max);
  EXPECT_EQ(argsOf("other", "5").integer("steps", 42, 1), 42);  // not given: the fallback
}

TEST(Args, WholeNumbersRefused) {
  // Beyond 64 bits (strtoll clamped these silently), either sign.
  for (const char* v : {"99999999999999999999", "9223372036854775808", "-99999999999999999999"}) {
    const std::string m = integerRefusal(v);
    EXPECT_NE(m.find("--steps expects a whole number"), std::string::npos) << v << ": " << m;
    EXPECT_NE(m.find("out of range"), std::string::npos) << v << ": " << m;
  }
  // Not a whole number, or more after it.
  for (const char* v : {"", "x", "7x", "1.5", "1e3", " 5", "5 ", "+", "-", "+-3", "0x10", "١"}) {
    EXPECT_NE(integerRefusal(v).find("--steps expects a whole number >= 0, got '"),
              std::string::npos)
        << "'" << v << "'";
  }
  // Out of the option's range, the bounds themselves taken.
  EXPECT_EQ(integerRefusal("-1"), "--steps expects a whole number >= 0, got '-1'");
  EXPECT_EQ(integerRefusal("0", 1), "--steps expects a whole number >= 1, got '0'");
  EXPECT_EQ(integerRefusal("1", 1), "");
  EXPECT_EQ(integerRefusal("10", 1, 10), "");
  EXPECT_EQ(integerRefusal("11", 1, 10), "--steps expects a whole number from 1 to 10, got '11'");
  // The default upper bound is an int's: a narrowing cast cannot wrap 2^32 + 1 to 1.
  const std::string m = refusal([] { argsOf("keep", "4294967297").integer("keep", 2, 1); });
  EXPECT_EQ(m, "--keep expects a whole number from 1 to 2147483647, got '4294967297'");
}

TEST(Args, Numbers) {
  EXPECT_EQ(argsOf("end-time", "0.25").number("end-time", 0.0), 0.25);
  EXPECT_EQ(argsOf("end-time", "+2.5e-3").number("end-time", 0.0), 2.5e-3);
  EXPECT_EQ(argsOf("end-time", "-3").number("end-time", 0.0), -3.0);
  EXPECT_EQ(argsOf("end-time", "7").number("end-time", 0.0, 7.0), 7.0);
  EXPECT_EQ(argsOf("other", "1").number("end-time", 0.5), 0.5);
}

TEST(Args, NumbersRefused) {
  EXPECT_EQ(numberRefusal("1e999"),
            "--end-time expects a finite number, got '1e999' (out of range)");
  for (const char* v : {"nan", "inf", "-inf", "infinity", "NAN", "", "2s", "1,5", "0x10", " 1",
                        "1 ", "+-1", "e5"}) {
    EXPECT_NE(numberRefusal(v).find("--end-time expects a finite number, got '"), std::string::npos)
        << "'" << v << "'";
  }
  EXPECT_EQ(numberRefusal("-1", 0.0), "--end-time expects a finite number >= 0, got '-1'");
}

TEST(Args, Lists) {
  auto list = [](const std::string& v) { return argsOf("ranks", v).integers("ranks", "", 1, 8); };
  EXPECT_EQ(list("1,2,8"), (std::vector<long long>{1, 2, 8}));
  EXPECT_EQ(argsOf("other", "").integers("ranks", "3,4", 1, 8), (std::vector<long long>{3, 4}));
  for (const char* v : {"1,,2", "1,2,", ",1", "1,9", "1,-2", "1;2", "1, 2", ""}) {
    EXPECT_NE(refusal([&] { list(v); }).find("--ranks expects a whole number from 1 to 8"),
              std::string::npos)
        << "'" << v << "'";
  }
}

}  // namespace
}  // namespace polydem::app
