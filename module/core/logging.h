// Rank-aware logging: information is printed once (by rank 0), warnings can come from any rank
// and then carry the rank number, errors go to stderr.
#pragma once

#include <string>

namespace polydem::log {

enum class Level { kQuiet = 0, kWarning = 1, kInfo = 2, kDetail = 3 };

void setLevel(Level level);
Level level();
/// Set by MpiEnvironment; only rank 0 prints info() and warning().
void setRank(int rank);

/// Progress and results, printed by rank 0 only.
void info(const std::string& message);
/// Extra detail (timings of sub-steps, iteration counts), rank 0 only.
void detail(const std::string& message);
/// A warning about the run as a whole (e.g. a too large time step), rank 0 only.
void warning(const std::string& message);
/// A warning about something local to this rank (e.g. a kernel not converging for one pair).
void rankWarning(const std::string& message);
/// An error message on stderr, from any rank.
void error(const std::string& message);

}  // namespace polydem::log
