#include "polydem/core/timing_pool.h"

#include <algorithm>
#include <cstdio>
#include <numeric>

#include "polydem/core/mpi_env.h"

namespace polydem {

void TimingPool::add(const std::string& name, double seconds) {
  auto it = std::find_if(entries_.begin(), entries_.end(),
                         [&](const Entry& e) { return e.name == name; });
  if (it == entries_.end()) {
    entries_.push_back({name, 0.0, 0});
    it = entries_.end() - 1;
  }
  it->seconds += seconds;
  it->count += 1;
  total_seconds_ += seconds;
}

double TimingPool::seconds(const std::string& name) const {
  for (const auto& e : entries_) {
    if (e.name == name) return e.seconds;
  }
  return 0.0;
}

TimingPool::Scope::Scope(TimingPool& pool, std::string name)
    : pool_(pool), name_(std::move(name)), start_(std::chrono::steady_clock::now()) {}

TimingPool::Scope::~Scope() {
  const auto end = std::chrono::steady_clock::now();
  pool_.add(name_, std::chrono::duration<double>(end - start_).count());
}

std::vector<TimingPool::Reduced> TimingPool::reduce(MPI_Comm comm) const {
  // Union of the names of all ranks, '\0'-separated, in rank order.
  std::vector<char> mine;
  for (const auto& e : entries_) {
    mine.insert(mine.end(), e.name.begin(), e.name.end());
    mine.push_back('\0');
  }
  const std::vector<char> all = mpi::allgatherv(mine, comm);
  std::vector<std::string> names;
  for (std::size_t start = 0; start < all.size();) {
    std::string name(&all[start]);
    start += name.size() + 1;
    if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
  }
  const std::size_t n = names.size();
  std::vector<double> secs(n, 0.0), lo(n), hi(n), sum(n);
  std::vector<std::int64_t> counts(n, 0), max_counts(n);
  for (std::size_t i = 0; i < n; ++i) {
    for (const auto& e : entries_) {
      if (e.name == names[i]) {
        secs[i] = e.seconds;
        counts[i] = e.count;
      }
    }
  }
  const int count_n = static_cast<int>(n);
  MPI_Allreduce(secs.data(), lo.data(), count_n, MPI_DOUBLE, MPI_MIN, comm);
  MPI_Allreduce(secs.data(), hi.data(), count_n, MPI_DOUBLE, MPI_MAX, comm);
  MPI_Allreduce(secs.data(), sum.data(), count_n, MPI_DOUBLE, MPI_SUM, comm);
  MPI_Allreduce(counts.data(), max_counts.data(), count_n, MPI_INT64_T, MPI_MAX, comm);
  const double ranks = mpi::size(comm);
  std::vector<Reduced> rows(n);
  double total = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    rows[i] = {names[i], lo[i], sum[i] / ranks, hi[i], max_counts[i], 0.0};
    total += rows[i].mean;
  }
  for (auto& r : rows) r.share = total > 0 ? r.mean / total : 0.0;
  return rows;
}

std::string TimingPool::table(const std::vector<Reduced>& rows, std::int64_t steps) {
  std::size_t width = 8;
  for (const auto& r : rows) width = std::max(width, r.name.size());
  std::string out;
  char line[512];
  std::snprintf(line, sizeof line, "%-*s %10s %10s %10s %7s %12s\n", static_cast<int>(width),
                "timer", "min [s]", "mean [s]", "max [s]", "share", "per step[ms]");
  out += line;
  for (const auto& r : rows) {
    const double per_step = steps > 0 ? 1e3 * r.mean / static_cast<double>(steps) : 0.0;
    std::snprintf(line, sizeof line, "%-*s %10.4f %10.4f %10.4f %6.1f%% %12.4f\n",
                  static_cast<int>(width), r.name.c_str(), r.min, r.mean, r.max, 100.0 * r.share,
                  per_step);
    out += line;
  }
  return out;
}

}  // namespace polydem
