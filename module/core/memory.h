// Memory this process may still use, so that a scene too large for the machine is refused with a
// clear message before it is built, instead of ending in std::bad_alloc after minutes of paging.
#pragma once

#include <cstdint>
#include <string>

namespace polydem {

/// Bytes this process can still allocate, about: the machine's available memory (MemAvailable
/// of /proc/meminfo, else the free physical pages), capped by the address-space limit (ulimit
/// -v) less what the process already maps. Shared by every process of the machine.
std::uint64_t availableMemoryBytes();

/// "1.5 GB", "820 MB", "12 kB": for messages.
std::string formatBytes(double bytes);

}  // namespace polydem
