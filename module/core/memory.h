// Memory this process may still use, so that a scene too large for the machine is refused with a
// clear message before it is built, instead of ending in std::bad_alloc after minutes of paging.
#pragma once

#include <algorithm>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

namespace polydem {

/// Bytes this process can still allocate, about: the machine's available memory (MemAvailable
/// of /proc/meminfo, else the free physical pages), capped by the address-space limit (ulimit
/// -v) less what the process already maps. Shared by every process of the machine.
std::uint64_t availableMemoryBytes();

/// "1.5 GB", "820 MB", "12 kB": for messages.
std::string formatBytes(double bytes);

/// The capacity to grow a table of `size` elements to when it is full: a quarter more (at least
/// 64), instead of the library's doubling. The tables sized by a step's pairs and sub-contacts
/// keep their capacity from step to step (a warm step allocates nothing); doubling would leave
/// them up to half empty for the whole run. The geometric growth keeps the copies while a table
/// first fills to a few times its size.
inline std::size_t growthFor(std::size_t size) {
  return size + std::max<std::size_t>(size / 4, 64);
}

/// Makes room for `n` elements, growing by growthFor when it must grow.
template <typename T, typename A>
void reserveFor(std::vector<T, A>& v, std::size_t n) {
  if (n > v.capacity()) v.reserve(std::max(n, growthFor(v.capacity())));
}

/// Heap bytes a vector holds: its capacity times its element size (room reserved counts as used,
/// as it does for the process). The same on any machine for the same build and input.
template <typename T, typename A>
std::uint64_t capacityBytes(const std::vector<T, A>& v) {
  return static_cast<std::uint64_t>(v.capacity()) * sizeof(T);
}

/// The same for vectors of vectors: the outer array and each inner one.
template <typename T, typename A, typename B>
std::uint64_t capacityBytes(const std::vector<std::vector<T, A>, B>& v) {
  std::uint64_t bytes = static_cast<std::uint64_t>(v.capacity()) * sizeof(std::vector<T, A>);
  for (const auto& inner : v) bytes += capacityBytes(inner);
  return bytes;
}

/// Heap bytes of an unordered_map, from its counts: the bucket array, and per element a node
/// holding the next pointer, the cached hash and the value (libstdc++'s largest node).
template <typename K, typename V, typename H, typename E, typename A>
std::uint64_t capacityBytes(const std::unordered_map<K, V, H, E, A>& m) {
  using Value = typename std::unordered_map<K, V, H, E, A>::value_type;
  return static_cast<std::uint64_t>(m.bucket_count()) * sizeof(void*) +
         static_cast<std::uint64_t>(m.size()) *
             (sizeof(void*) + sizeof(std::size_t) + sizeof(Value));
}

}  // namespace polydem
