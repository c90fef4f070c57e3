#include "polydem/comm/history_routing.h"

#include <algorithm>
#include <map>
#include <unordered_map>
#include <vector>

#include "polydem/comm/sparse_exchange.h"
#include "polydem/core/error.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/strings.h"

namespace polydem::comm {

namespace {

using particles::HistoryRecords;
using particles::PairHistory;
using particles::PairKey;
using particles::SubHistory;
using particles::SubKey;

constexpr int kRegisterTag = 7303;
constexpr int kDeliverTag = 7304;

// Record types of round 1.
constexpr std::uint8_t kOwner = 0;     // uid, owning rank
constexpr std::uint8_t kHistory = 1;   // the member uid this directory answers for, then a record
constexpr std::uint8_t kEveryone = 2;  // a record of two replicated particles: keep it

// What a history record carries: a pair's history or one of its sub-contacts'.
constexpr std::uint8_t kPairPayload = 0;
constexpr std::uint8_t kSubPayload = 1;

int directoryOf(Uid uid, int ranks) {
  return static_cast<int>(uid % static_cast<Uid>(ranks));
}

void packRecord(SendBuffer& out, const HistoryRecords& r, bool sub, std::size_t i) {
  out << (sub ? kSubPayload : kPairPayload);
  if (sub) {
    pack(out, r.sub_keys[i], r.sub_entries[i]);
  } else {
    pack(out, r.keys[i], r.entries[i]);
  }
}

// Reads one record into `into`; returns its pair key, whether it is a sub-contact, and its index.
struct Unpacked {
  PairKey pair;
  bool sub;
  std::size_t index;
};
Unpacked unpackRecord(RecvBuffer& in, HistoryRecords& into) {
  std::uint8_t payload = 0;
  in >> payload;
  if (payload == kSubPayload) {
    SubKey k;
    SubHistory h;
    unpack(in, k, h);
    into.sub_keys.push_back(k);
    into.sub_entries.push_back(h);
    return {k.pair, true, into.sub_keys.size() - 1};
  }
  PairKey k;
  PairHistory h;
  unpack(in, k, h);
  into.keys.push_back(k);
  into.entries.push_back(h);
  return {k, false, into.keys.size() - 1};
}

// Uids of replicated particles, sorted for lookup.
class ReplicatedSet {
 public:
  explicit ReplicatedSet(std::span<const Uid> uids) : uids_(uids.begin(), uids.end()) {
    std::sort(uids_.begin(), uids_.end());
  }
  bool contains(Uid u) const { return std::binary_search(uids_.begin(), uids_.end(), u); }

 private:
  std::vector<Uid> uids_;
};

// Particles without exactly one owner, counted on this rank; the last one seen as the example.
struct Problems {
  std::int64_t count = 0;
  Uid example = 0;
  void add(Uid uid) {
    ++count;
    example = uid;
  }
};

void requireMatchingSizes(const HistoryRecords& records) {
  if (records.keys.size() != records.entries.size() ||
      records.sub_keys.size() != records.sub_entries.size()) {
    throw Error(cat("routeHistories: ", records.keys.size(), " keys but ", records.entries.size(),
                    " histories, ", records.sub_keys.size(), " sub-contact keys but ",
                    records.sub_entries.size(), " sub-contact histories"));
  }
}

// Round 1, sending: every owned uid registers its owner at its directory; every record goes to
// the directories of its non-replicated members, or to every rank if both are replicated.
std::map<int, SendBuffer> registrations(const HistoryRecords& records, std::span<const Uid> owned,
                                        const ReplicatedSet& replicated, int rank, int ranks,
                                        HistoryRoutingStats& stats) {
  std::map<int, SendBuffer> outgoing;
  for (Uid u : owned) {
    outgoing[directoryOf(u, ranks)] << kOwner << u << static_cast<std::int32_t>(rank);
    ++stats.registered;
  }
  auto send = [&](const PairKey& k, bool sub, std::size_t i) {
    if (replicated.contains(k.lo) && replicated.contains(k.hi)) {
      for (int r = 0; r < ranks; ++r) {
        outgoing[r] << kEveryone;
        packRecord(outgoing[r], records, sub, i);
      }
      return;
    }
    for (Uid member : {k.lo, k.hi}) {
      if (replicated.contains(member)) continue;
      SendBuffer& out = outgoing[directoryOf(member, ranks)];
      out << kHistory << member;
      packRecord(out, records, sub, i);
    }
  };
  for (std::size_t i = 0; i < records.keys.size(); ++i) send(records.keys[i], false, i);
  for (std::size_t i = 0; i < records.sub_keys.size(); ++i) send(records.sub_keys[i].pair, true, i);
  return outgoing;
}

// Round 1, receiving: what this rank's directory learnt. Records of two replicated particles go
// straight to `kept`; the others wait in `arrived` for their member's owner.
struct Directory {
  std::unordered_map<Uid, int> owner_of;
  HistoryRecords arrived;
  std::vector<std::pair<Uid, Unpacked>> waiting;  // (member, record in `arrived`)
};

Directory receiveRegistrations(const std::map<int, SendBuffer>& outgoing, MPI_Comm comm,
                               HistoryRecords& kept, Problems& problems) {
  Directory directory;
  for (const auto& m : sparseExchange(outgoing, comm, kRegisterTag)) {
    RecvBuffer in(m.bytes.data(), m.bytes.size());
    while (!in.atEnd()) {
      std::uint8_t type = 0;
      in >> type;
      if (type == kOwner) {
        Uid u = 0;
        std::int32_t owner = 0;
        in >> u >> owner;
        if (!directory.owner_of.emplace(u, owner).second) problems.add(u);  // two owners
      } else if (type == kHistory) {
        Uid member = 0;
        in >> member;
        directory.waiting.push_back({member, unpackRecord(in, directory.arrived)});
      } else {
        unpackRecord(in, kept);
      }
    }
  }
  return directory;
}

// Round 2: the directory forwards each waiting record to its member's owner, which keeps it.
void forwardToOwners(const Directory& directory, MPI_Comm comm, HistoryRecords& kept,
                     Problems& problems, HistoryRoutingStats& stats) {
  std::map<int, SendBuffer> outgoing;
  for (const auto& [member, record] : directory.waiting) {
    const auto it = directory.owner_of.find(member);
    if (it == directory.owner_of.end()) {
      problems.add(member);  // a pair with a particle nobody owns
      continue;
    }
    packRecord(outgoing[it->second], directory.arrived, record.sub, record.index);
    stats.forwarded += !record.sub;
  }
  for (const auto& m : sparseExchange(outgoing, comm, kDeliverTag)) {
    RecvBuffer in(m.bytes.data(), m.bytes.size());
    while (!in.atEnd()) unpackRecord(in, kept);
  }
}

// Collective: if any rank found a problem, every rank throws, naming the smallest example uid.
void agreeOnProblems(const Problems& problems, MPI_Comm comm) {
  const std::int64_t total = mpi::allreduceSum(problems.count, comm);
  if (total == 0) return;
  Uid first = problems.count > 0 ? problems.example : ~Uid{0};
  MPI_Allreduce(MPI_IN_PLACE, &first, 1, MPI_UINT64_T, MPI_MIN, comm);
  throw Error(cat("routeHistories: ", total,
                  " pair histories or uids without exactly one owner (e.g. particle uid ", first,
                  ")"));
}

}  // namespace

// Two rounds through directories (rank uid % P answers for uid): owners and records meet at the
// directories, which forward each record to the owners of its particles.
particles::ContactHistory routeHistories(const HistoryRecords& records, std::span<const Uid> owned,
                                         std::span<const Uid> replicated, MPI_Comm comm,
                                         HistoryRoutingStats* stats) {
  requireMatchingSizes(records);
  const int rank = mpi::rank(comm), ranks = mpi::size(comm);
  const ReplicatedSet everywhere(replicated);
  HistoryRoutingStats local_stats;
  Problems problems;
  HistoryRecords kept;
  const Directory directory = receiveRegistrations(
      registrations(records, owned, everywhere, rank, ranks, local_stats), comm, kept, problems);
  forwardToOwners(directory, comm, kept, problems, local_stats);
  agreeOnProblems(problems, comm);
  // Copies of one record (from its two directories) are the same: merge keeps one.
  particles::ContactHistory out;
  out.merge(kept);
  local_stats.kept = static_cast<std::int64_t>(out.size());
  if (stats) *stats = local_stats;
  return out;
}

particles::ContactHistory routeHistories(std::span<const PairKey> keys,
                                         std::span<const PairHistory> entries,
                                         std::span<const Uid> owned,
                                         std::span<const Uid> replicated, MPI_Comm comm,
                                         HistoryRoutingStats* stats) {
  HistoryRecords records;
  records.keys.assign(keys.begin(), keys.end());
  records.entries.assign(entries.begin(), entries.end());
  return routeHistories(records, owned, replicated, comm, stats);
}

namespace {
void ownedAndReplicated(const particles::ParticleStorage& storage, std::vector<Uid>& owned,
                        std::vector<Uid>& replicated) {
  for (std::size_t i = 0; i < storage.localCount(); ++i) {
    const auto& p = storage[i];
    (p.isGlobal() ? replicated : owned).push_back(p.uid);
  }
}
}  // namespace

particles::ContactHistory routeHistories(const HistoryRecords& records,
                                         const particles::ParticleStorage& storage, MPI_Comm comm,
                                         HistoryRoutingStats* stats) {
  std::vector<Uid> owned, replicated;
  ownedAndReplicated(storage, owned, replicated);
  return routeHistories(records, owned, replicated, comm, stats);
}

particles::ContactHistory routeHistories(std::span<const PairKey> keys,
                                         std::span<const PairHistory> entries,
                                         const particles::ParticleStorage& storage, MPI_Comm comm,
                                         HistoryRoutingStats* stats) {
  std::vector<Uid> owned, replicated;
  ownedAndReplicated(storage, owned, replicated);
  return routeHistories(keys, entries, owned, replicated, comm, stats);
}

}  // namespace polydem::comm
