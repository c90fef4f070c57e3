#include "polydem/comm/history_routing.h"

#include <algorithm>
#include <map>
#include <unordered_map>
#include <vector>

#include "polydem/comm/sparse_exchange.h"
#include "polydem/core/error.h"
#include "polydem/core/memory.h"
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
constexpr int kHistoryTag = 7306;

// Record types of round 1.
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

// Particles without exactly one owner, counted on this rank; the last one seen as the example.
struct Problems {
  std::int64_t count = 0;
  Uid example = 0;
  void add(Uid uid) {
    ++count;
    example = uid;
  }
};

bool isReplicated(const std::vector<Uid>& sorted, Uid u) {
  return std::binary_search(sorted.begin(), sorted.end(), u);
}

void requireMatchingSizes(const HistoryRecords& records) {
  if (records.keys.size() != records.entries.size() ||
      records.sub_keys.size() != records.sub_entries.size()) {
    throw Error(cat("routeHistories: ", records.keys.size(), " keys but ", records.entries.size(),
                    " histories, ", records.sub_keys.size(), " sub-contact keys but ",
                    records.sub_entries.size(), " sub-contact histories"));
  }
}

std::uint64_t messageBytes(const std::map<int, SendBuffer>& messages) {
  std::uint64_t bytes = 0;
  for (const auto& [rank, out] : messages) bytes += out.bytes().capacity();
  return bytes;
}

std::uint64_t messageBytes(const std::vector<Message>& messages) {
  std::uint64_t bytes = 0;
  for (const auto& m : messages) bytes += m.bytes.capacity();
  return bytes;
}

std::uint64_t recordBytes(const HistoryRecords& r) {
  return capacityBytes(r.keys) + capacityBytes(r.entries) + capacityBytes(r.sub_keys) +
         capacityBytes(r.sub_entries);
}

// Round 1, sending: every record goes to the directories of its non-replicated members, or to
// every rank if both are replicated.
std::map<int, SendBuffer> toDirectories(const HistoryRecords& records,
                                        const std::vector<Uid>& replicated, int ranks) {
  std::map<int, SendBuffer> outgoing;
  auto send = [&](const PairKey& k, bool sub, std::size_t i) {
    if (isReplicated(replicated, k.lo) && isReplicated(replicated, k.hi)) {
      for (int r = 0; r < ranks; ++r) {
        outgoing[r] << kEveryone;
        packRecord(outgoing[r], records, sub, i);
      }
      return;
    }
    for (Uid member : {k.lo, k.hi}) {
      if (isReplicated(replicated, member)) continue;
      SendBuffer& out = outgoing[directoryOf(member, ranks)];
      out << kHistory << member;
      packRecord(out, records, sub, i);
    }
  };
  for (std::size_t i = 0; i < records.keys.size(); ++i) send(records.keys[i], false, i);
  for (std::size_t i = 0; i < records.sub_keys.size(); ++i) send(records.sub_keys[i].pair, true, i);
  return outgoing;
}

// Round 1, receiving: records of two replicated particles go straight to `kept`; the others wait
// in `arrived` for their member's owner.
struct Directory {
  HistoryRecords arrived;
  std::vector<std::pair<Uid, Unpacked>> waiting;  // (member, record in `arrived`)
};

Directory receiveAtDirectory(const std::vector<Message>& messages, HistoryRecords& kept) {
  Directory directory;
  for (const auto& m : messages) {
    RecvBuffer in(m.bytes.data(), m.bytes.size());
    while (!in.atEnd()) {
      std::uint8_t type = 0;
      in >> type;
      if (type == kHistory) {
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

// Round 2, sending: the directory forwards each waiting record to its member's owner.
std::map<int, SendBuffer> toOwners(const Directory& directory,
                                   const std::unordered_map<Uid, int>& owner_of, Problems& problems,
                                   HistoryRoutingStats& stats) {
  std::map<int, SendBuffer> outgoing;
  for (const auto& [member, record] : directory.waiting) {
    const auto it = owner_of.find(member);
    if (it == owner_of.end()) {
      problems.add(member);  // a pair with a particle nobody owns
      continue;
    }
    packRecord(outgoing[it->second], directory.arrived, record.sub, record.index);
    stats.forwarded += !record.sub;
  }
  return outgoing;
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

void ownedAndReplicated(const particles::ParticleStorage& storage, std::vector<Uid>& owned,
                        std::vector<Uid>& replicated) {
  for (std::size_t i = 0; i < storage.localCount(); ++i) {
    const auto& p = storage[i];
    (p.isGlobal() ? replicated : owned).push_back(p.uid);
  }
}

}  // namespace

// Every owned uid registers its owner at its directory (rank uid % P), once for all chunks.
HistoryRouter::HistoryRouter(std::span<const Uid> owned, std::span<const Uid> replicated,
                             MPI_Comm comm)
    : comm_(comm),
      rank_(mpi::rank(comm)),
      ranks_(mpi::size(comm)),
      replicated_(replicated.begin(), replicated.end()) {
  std::sort(replicated_.begin(), replicated_.end());
  std::map<int, SendBuffer> outgoing;
  for (Uid u : owned) {
    outgoing[directoryOf(u, ranks_)] << u << static_cast<std::int32_t>(rank_);
    ++stats_.registered;
  }
  Problems problems;
  for (const auto& m : sparseExchange(outgoing, comm_, kRegisterTag)) {
    RecvBuffer in(m.bytes.data(), m.bytes.size());
    while (!in.atEnd()) {
      Uid u = 0;
      std::int32_t owner = 0;
      in >> u >> owner;
      if (!owner_of_.emplace(u, owner).second) problems.add(u);  // two owners
    }
  }
  agreeOnProblems(problems, comm_);
}

HistoryRouter::HistoryRouter(const particles::ParticleStorage& storage, MPI_Comm comm)
    : HistoryRouter([&] {
        std::vector<Uid> owned, replicated;
        ownedAndReplicated(storage, owned, replicated);
        return HistoryRouter(owned, replicated, comm);
      }()) {}

// Two rounds through the directories, which forward each record to the owners of its particles.
void HistoryRouter::route(const HistoryRecords& chunk, particles::ContactHistory& into) {
  requireMatchingSizes(chunk);
  Problems problems;
  HistoryRecords kept;
  std::uint64_t transit = 0;
  {
    std::vector<Message> arriving;
    {
      const auto outgoing = toDirectories(chunk, replicated_, ranks_);
      arriving = sparseExchange(outgoing, comm_, kHistoryTag);
      transit = messageBytes(outgoing) + messageBytes(arriving);
    }
    const Directory directory = receiveAtDirectory(arriving, kept);
    transit = std::max(transit,
                       messageBytes(arriving) + recordBytes(directory.arrived) + recordBytes(kept));
    arriving = {};
    const auto forwarding = toOwners(directory, owner_of_, problems, stats_);
    const auto delivered = sparseExchange(forwarding, comm_, kDeliverTag);
    transit = std::max(transit, recordBytes(directory.arrived) + messageBytes(forwarding) +
                                    messageBytes(delivered) + recordBytes(kept));
    for (const auto& m : delivered) {
      RecvBuffer in(m.bytes.data(), m.bytes.size());
      while (!in.atEnd()) unpackRecord(in, kept);
    }
    transit = std::max(transit, messageBytes(delivered) + recordBytes(kept));
  }
  agreeOnProblems(problems, comm_);
  // Copies of one record (from its two directories) are the same: the assembly keeps one.
  const std::uint64_t kept_bytes = recordBytes(kept);
  into.appendRecords(std::move(kept));
  stats_.peak_transit_bytes = std::max(stats_.peak_transit_bytes, transit + kept_bytes);
  ++stats_.chunks;
}

void HistoryRouter::finish(particles::ContactHistory& into) {
  into.endAssembly();
  stats_.kept = static_cast<std::int64_t>(into.size());
}

particles::ContactHistory routeHistories(const HistoryRecords& records, std::span<const Uid> owned,
                                         std::span<const Uid> replicated, MPI_Comm comm,
                                         HistoryRoutingStats* stats) {
  HistoryRouter router(owned, replicated, comm);
  particles::ContactHistory out;
  out.beginAssembly();
  router.route(records, out);
  router.finish(out);
  if (stats) *stats = router.stats();
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
