#include "polydem/core/test_pause.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>

namespace polydem {

namespace {

/// Seconds POLYDEM_TEST_PAUSE gives for `where`, or 0.
double pauseSeconds(std::string_view where) {
  const char* value = std::getenv("POLYDEM_TEST_PAUSE");
  if (value == nullptr) return 0.0;
  std::string_view list(value);
  while (!list.empty()) {
    const auto comma = list.find(',');
    const std::string_view item = list.substr(0, comma);
    const auto colon = item.find(':');
    if (colon != std::string_view::npos && item.substr(0, colon) == where) {
      return std::strtod(std::string(item.substr(colon + 1)).c_str(), nullptr);
    }
    if (comma == std::string_view::npos) break;
    list.remove_prefix(comma + 1);
  }
  return 0.0;
}

}  // namespace

void testPause(std::string_view where) {
  const double seconds = pauseSeconds(where);
  if (!(seconds > 0.0)) return;
  std::fprintf(stderr, "polydem test pause: %.*s, %g s (pid %ld)\n", static_cast<int>(where.size()),
               where.data(), seconds, static_cast<long>(::getpid()));
  std::fflush(stderr);
  // nanosleep returns early when a signal handler runs: sleep on until the time is up.
  timespec left{
      static_cast<time_t>(seconds),
      static_cast<long>((seconds - static_cast<double>(static_cast<time_t>(seconds))) * 1e9)};
  while (::nanosleep(&left, &left) != 0 && errno == EINTR) {
  }
}

}  // namespace polydem
