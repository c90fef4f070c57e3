// A scene whose particles cannot fit in memory is refused where it asks for them (a
// [[particle_grid]] count), before anything is built.
#include "polydem/core/memory.h"
#include "polydem/core/strings.h"
#include "polydem/scene/scene_sections.h"

namespace polydem::scene::detail {

namespace {

/// Memory of one particle in a run on one rank, measured: 1.4 kB each for grids of 64,000 and
/// 256,000 cubes (maximum resident set of `polydem run` over one step, the difference divided by
/// the difference in count), rounded up. Ranks hold every particle's scene entry and their share
/// of the simulation, so several ranks on one machine need more.
constexpr double kBytesPerParticle = 1500.0;

}  // namespace

void checkParticleMemory(const Section& s, std::string_view key, std::uint64_t particles) {
  const double needed = kBytesPerParticle * static_cast<double>(particles);
  const double available = static_cast<double>(availableMemoryBytes());
  if (available > 0.0 && needed > available) {
    s.fail(key,
           cat("the scene would have ", particles, " particles, which need about ",
               formatBytes(needed), " (", formatBytes(kBytesPerParticle), " each), more than the ",
               formatBytes(available), " of memory available on this machine"));
  }
}

}  // namespace polydem::scene::detail
