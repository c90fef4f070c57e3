#include "polydem/core/memory.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <string>

namespace polydem {

namespace {

/// A "Key:   123 kB" line of a /proc file, in bytes, or 0.
std::uint64_t procValue(const char* file, const std::string& key) {
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line)) {
    if (line.compare(0, key.size(), key) != 0 || line.size() <= key.size() ||
        line[key.size()] != ':') {
      continue;
    }
    unsigned long long kb = 0;
    if (std::sscanf(line.c_str() + key.size() + 1, "%llu", &kb) == 1) return kb * 1024ULL;
  }
  return 0;
}

}  // namespace

std::uint64_t availableMemoryBytes() {
  std::uint64_t available = procValue("/proc/meminfo", "MemAvailable");
  if (available == 0) {
    const long pages = ::sysconf(_SC_AVPHYS_PAGES), size = ::sysconf(_SC_PAGESIZE);
    if (pages > 0 && size > 0) available = static_cast<std::uint64_t>(pages) * size;
  }
  rlimit limit{};
  if (::getrlimit(RLIMIT_AS, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY) {
    const std::uint64_t mapped = procValue("/proc/self/status", "VmSize");
    const std::uint64_t room = limit.rlim_cur > mapped ? limit.rlim_cur - mapped : 0;
    available = available == 0 ? room : std::min(available, room);
  }
  return available;
}

std::string formatBytes(double bytes) {
  const char* units[] = {"bytes", "kB", "MB", "GB", "TB", "PB"};
  int u = 0;
  while (bytes >= 1000.0 && u < 5) {
    bytes /= 1000.0;
    ++u;
  }
  char text[32];
  std::snprintf(text, sizeof text, u == 0 ? "%.0f %s" : "%.3g %s", bytes, units[u]);
  return text;
}

}  // namespace polydem
