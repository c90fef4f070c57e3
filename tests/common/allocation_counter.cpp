#include "common/allocation_counter.h"

#include <atomic>
#include <cstdlib>
#include <new>

namespace {
std::atomic<long> g_allocations{0};
std::atomic<long long> g_bytes{0};
}  // namespace

// Counting replacements of the global allocation functions, forwarding to malloc/free. GCC
// cannot tell that these replacements pair malloc with free themselves, hence the pragma.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void* operator new(std::size_t size) {
  ++g_allocations;
  g_bytes += static_cast<long long>(size);
  if (void* p = std::malloc(size > 0 ? size : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}
#pragma GCC diagnostic pop

namespace polydem::testing {

long allocationCount() {
  return g_allocations.load();
}

long long allocatedBytes() {
  return g_bytes.load();
}

}  // namespace polydem::testing
