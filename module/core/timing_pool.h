// Named wall-clock timers in waLBerla's manner: every timeloop function, communication phase and
// output step adds its time here; at the end the pool is reduced over ranks (min / mean / max)
// and printed as a table with each entry's share of the total.
#pragma once

#include <mpi.h>

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

namespace polydem {

class TimingPool {
 public:
  struct Entry {
    std::string name;
    double seconds = 0.0;
    std::int64_t count = 0;
  };
  struct Reduced {
    std::string name;
    double min = 0.0, mean = 0.0, max = 0.0;  // seconds, over ranks
    std::int64_t count = 0;                   // calls on rank 0 (or the max over ranks)
    double share = 0.0;                       // mean / sum of means
  };

  /// Adds one timed call of `name`.
  void add(const std::string& name, double seconds);

  /// RAII timer: TimingPool::Scope s = pool.scope("broadphase");
  class Scope {
   public:
    Scope(TimingPool& pool, std::string name);
    ~Scope();
    Scope(const Scope&) = delete;
    Scope& operator=(const Scope&) = delete;

   private:
    TimingPool& pool_;
    std::string name_;
    std::chrono::steady_clock::time_point start_;
  };
  Scope scope(std::string name) { return Scope(*this, std::move(name)); }

  const std::vector<Entry>& entries() const { return entries_; }
  double seconds(const std::string& name) const;
  /// The seconds of all calls added so far: a timer around work that times parts of itself into
  /// the pool takes their difference off its own row, so that no second is counted twice.
  double totalSeconds() const { return total_seconds_; }
  void clear() {
    entries_.clear();
    total_seconds_ = 0.0;
  }

  /// Collective over `comm`: the union of all names (rank 0's order first), with min, mean and
  /// max over ranks. Every rank gets the same result.
  std::vector<Reduced> reduce(MPI_Comm comm) const;

  /// A fixed-width text table of a reduced pool; `steps` > 0 adds a per-step column.
  static std::string table(const std::vector<Reduced>& rows, std::int64_t steps);

 private:
  std::vector<Entry> entries_;
  double total_seconds_ = 0.0;
};

}  // namespace polydem
