#include "polydem/core/logging.h"

#include <cstdio>

namespace polydem::log {

namespace {
Level g_level = Level::kInfo;
int g_rank = 0;

void print(std::FILE* stream, const std::string& prefix, const std::string& message) {
  std::fprintf(stream, "%s%s\n", prefix.c_str(), message.c_str());
  std::fflush(stream);
}
}  // namespace

void setLevel(Level level) {
  g_level = level;
}
Level level() {
  return g_level;
}
void setRank(int rank) {
  g_rank = rank;
}

void info(const std::string& message) {
  if (g_rank == 0 && g_level >= Level::kInfo) print(stdout, "", message);
}

void detail(const std::string& message) {
  if (g_rank == 0 && g_level >= Level::kDetail) print(stdout, "  ", message);
}

void warning(const std::string& message) {
  if (g_rank == 0 && g_level >= Level::kWarning) print(stderr, "warning: ", message);
}

void rankWarning(const std::string& message) {
  if (g_level >= Level::kWarning) {
    print(stderr, "warning (rank " + std::to_string(g_rank) + "): ", message);
  }
}

void error(const std::string& message) {
  print(stderr, "error: ", message);
}

}  // namespace polydem::log
