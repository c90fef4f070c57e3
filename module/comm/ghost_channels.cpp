#include "polydem/comm/ghost_channels.h"

#include <algorithm>

#include "polydem/core/error.h"
#include "polydem/core/memory.h"
#include "polydem/core/strings.h"

namespace polydem::comm {

namespace {

using particles::Particle;

bool sameKey(const Particle& a, const domain::Index3& ia, const Particle& b,
             const domain::Index3& ib) {
  return a.uid == b.uid && ia == ib;
}

bool keyLess(const Particle& a, const domain::Index3& ia, const Particle& b,
             const domain::Index3& ib) {
  return a.uid != b.uid ? a.uid < b.uid : ia < ib;
}

// What a ghost keeps from one exchange to the next (never changed by a step).
bool sameStaticFields(const Particle& a, const Particle& b) {
  return a.shape == b.shape && a.material == b.material && a.flags == b.flags &&
         a.driver == b.driver;
}

void packUpdate(SendBuffer& out, const Particle& p) {
  out << p.position << p.orientation << p.velocity << p.angular_momentum;
}

void unpackUpdate(RecvBuffer& in, Particle& p) {
  in >> p.position >> p.orientation >> p.velocity >> p.angular_momentum;
}

void packWhole(SendBuffer& out, const Particle& p, const domain::Index3& image) {
  pack(out, p);
  for (int a = 0; a < 3; ++a) out << static_cast<std::int16_t>(image[a]);
}

void unpackWhole(RecvBuffer& in, Particle& p, domain::Index3& image) {
  unpack(in, p);
  for (int a = 0; a < 3; ++a) {
    std::int16_t i = 0;
    in >> i;
    image[a] = i;
  }
}

}  // namespace

void GhostChannels::reset() {
  channels_.clear();
}

void GhostChannels::queue(int rank, const Particle& p, const domain::Index3& image) {
  channels_[rank].queued.push_back({p, image});
}

// kept_[j]: whether held ghost j (sent[j]) is queued again, unchanged but for its state; used_[q]:
// whether queued ghost q is such a kept one. The queue is looked up sorted by (uid, image).
void GhostChannels::packChannel(Channel& c, SendBuffer& out, GhostCounts& counts) {
  const auto& q = c.queued;
  order_.resize(q.size());
  for (std::uint32_t i = 0; i < q.size(); ++i) order_[i] = i;
  std::sort(order_.begin(), order_.end(), [&q](std::uint32_t a, std::uint32_t b) {
    return keyLess(q[a].p, q[a].image, q[b].p, q[b].image);
  });
  used_.assign(q.size(), 0);
  kept_.assign(c.sent.size(), 0);
  next_.clear();
  for (std::size_t j = 0; j < c.sent.size() && compact_; ++j) {
    const auto& s = c.sent[j];
    const auto it =
        std::lower_bound(order_.begin(), order_.end(), s, [&q](std::uint32_t a, const Queued& k) {
          return keyLess(q[a].p, q[a].image, k.p, k.image);
        });
    if (it == order_.end() || !sameKey(q[*it].p, q[*it].image, s.p, s.image)) continue;
    if (!sameStaticFields(q[*it].p, s.p)) continue;
    kept_[j] = 1;
    used_[*it] = 1;
    next_.push_back(q[*it]);
  }
  out << static_cast<std::uint32_t>(c.sent.size());
  for (std::size_t j = 0; j < c.sent.size(); j += 8) {
    std::uint8_t bits = 0;
    for (std::size_t b = 0; b < 8 && j + b < c.sent.size(); ++b) bits |= kept_[j + b] << b;
    out << bits;
  }
  for (const auto& k : next_) packUpdate(out, k.p);
  counts.updates += static_cast<std::int64_t>(next_.size());
  const std::size_t kept = next_.size();
  out << static_cast<std::uint32_t>(q.size() - kept);
  for (std::size_t i = 0; i < q.size(); ++i) {
    if (used_[i]) continue;
    packWhole(out, q[i].p, q[i].image);
    next_.push_back(q[i]);
  }
  counts.whole += static_cast<std::int64_t>(next_.size() - kept);
  std::swap(c.sent, next_);
  c.queued.clear();
}

GhostCounts GhostChannels::pack(const std::map<int, SendBuffer>& records,
                                std::map<int, SendBuffer>& outgoing) {
  GhostCounts counts;
  for (auto& [rank, c] : channels_) {
    if (c.sent.empty() && c.queued.empty()) continue;
    packChannel(c, outgoing[rank], counts);
  }
  for (const auto& [rank, r] : records) {
    SendBuffer& out = outgoing[rank];
    if (out.size() == 0) out << std::uint32_t{0} << std::uint32_t{0};  // no ghosts, then records
    out.append(r.bytes().data(), r.size());
  }
  return counts;
}

GhostCounts GhostChannels::unpack(int rank, RecvBuffer& in) {
  GhostCounts counts;
  auto it = channels_.find(rank);
  if (in.atEnd()) {
    if (it != channels_.end() && !it->second.held.empty()) {
      throw Error(cat("ghost exchange: rank ", rank, " sent nothing, but ", it->second.held.size(),
                      " of its ghosts are held here (out of step)"));
    }
    return counts;
  }
  Channel& c = it != channels_.end() ? it->second : channels_[rank];
  std::uint32_t held = 0;
  in >> held;
  if (held != c.held.size()) {
    throw Error(cat("ghost exchange: rank ", rank, " thinks ", held,
                    " of its ghosts are held here, ", "but ", c.held.size(), " are (out of step)"));
  }
  // Kept ghosts move forward in place, in their order, and take their new state.
  std::size_t w = 0;
  for (std::size_t j = 0; j < held; j += 8) {
    std::uint8_t bits = 0;
    in >> bits;
    for (std::size_t b = 0; b < 8 && j + b < held; ++b) {
      if (!(bits >> b & 1u)) continue;
      c.held[w] = c.held[j + b];
      c.held_image[w] = c.held_image[j + b];
      ++w;
    }
  }
  c.held.resize(w);
  c.held_image.resize(w);
  for (auto& p : c.held) unpackUpdate(in, p);
  counts.updates = static_cast<std::int64_t>(w);
  std::uint32_t fresh = 0;
  in >> fresh;
  for (std::uint32_t i = 0; i < fresh; ++i) {
    c.held.emplace_back();
    c.held_image.emplace_back();
    unpackWhole(in, c.held.back(), c.held_image.back());
  }
  counts.whole = fresh;
  return counts;
}

std::uint64_t GhostChannels::heapBytes() const {
  std::uint64_t bytes =
      capacityBytes(order_) + capacityBytes(used_) + capacityBytes(kept_) + capacityBytes(next_);
  for (const auto& [rank, c] : channels_) {
    bytes += capacityBytes(c.sent) + capacityBytes(c.queued) + capacityBytes(c.held) +
             capacityBytes(c.held_image);
  }
  return bytes;
}

}  // namespace polydem::comm
