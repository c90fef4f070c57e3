#include "polydem/broadphase/sphere_tests.h"

#include <atomic>
#include <string>

#include "polydem/core/error.h"

namespace polydem::broadphase::detail {

namespace {

// The CPU's answer is asked once; GCC's check includes the operating system's support for the
// 256-bit registers (XGETBV), not only the CPUID bit.
TestLanes detectWidest() {
#if POLYDEM_BROADPHASE_AVX2
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx2")) return TestLanes::kFour;
#endif
  return TestLanes::kTwo;
}

// Process-wide; relaxed: the width changes no result, only the speed.
std::atomic<int> lanes_set{0};  // 0: not set

}  // namespace

TestLanes widestTestLanes() {
  static const TestLanes widest = detectWidest();
  return widest;
}

TestLanes testLanes() {
  const int set = lanes_set.load(std::memory_order_relaxed);
  return set == 0 ? widestTestLanes() : static_cast<TestLanes>(set);
}

void setTestLanes(TestLanes lanes) {
  if (static_cast<int>(lanes) > static_cast<int>(widestTestLanes())) {
    throw Error("broad phase: " + std::to_string(static_cast<int>(lanes)) +
                "-lane sphere tests need AVX2, which this CPU or build lacks");
  }
  lanes_set.store(static_cast<int>(lanes), std::memory_order_relaxed);
}

}  // namespace polydem::broadphase::detail
