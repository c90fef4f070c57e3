// What a rank's simulation holds on the heap, by structure, counted from what is allocated
// (capacity times element size, core/memory.h), not measured from the process: the same figures
// on any machine for the same build and input, so that a test can bound them. Glibc's own
// overhead per allocation, the MPI library and the program's code are not in them.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace polydem::sim {

struct MemoryItem {
  std::string name;  // short, for a table
  std::string what;  // what it holds
  std::uint64_t bytes = 0;
};

/// The items in a fixed order (the same names on every rank and every call).
using MemoryUse = std::vector<MemoryItem>;

inline std::uint64_t totalBytes(const MemoryUse& use) {
  std::uint64_t sum = 0;
  for (const auto& item : use) sum += item.bytes;
  return sum;
}

}  // namespace polydem::sim
