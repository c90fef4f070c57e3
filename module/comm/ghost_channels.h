// What travels of a ghost copy from one exchange to the next.
//
// A rank that sends ghosts to a neighbour remembers which ones (uid and periodic image) and in
// what order; the neighbour holds its copies in the same order. At the next exchange a ghost that
// stays a ghost there (same particle, same image, same shape, material, flags and driver) needs
// only its changing state: position, orientation, velocity and angular momentum (104 bytes, the
// fields integration changes); a new ghost travels whole (128 bytes and its 6-byte image). The
// ghost section that opens every message:
//
//     u32 held     ghosts the receiver holds from this sender (a check)
//     held bits    1: kept (in the held order), 0: dropped
//     updates      the changing state of each kept ghost, in the held order
//     u32 new      ghosts new to the receiver
//     records      each new ghost whole with its image, in the sender's order
//
// The receiver's copies end up bit for bit what a full record would give. Their order (kept ones
// in their old order, then the new ones; senders by rank) is a function of the messages alone.
// reset() forgets everything, on every rank at once (a collective call of the exchange): after it
// every ghost is new.
#pragma once

#include <cstdint>
#include <map>
#include <vector>

#include "polydem/core/byte_buffer.h"
#include "polydem/domain/block_forest.h"
#include "polydem/particles/particle.h"

namespace polydem::comm {

struct GhostCounts {
  std::int64_t whole = 0;    // ghosts sent or received whole
  std::int64_t updates = 0;  // ghosts sent or received as a state update
};

class GhostChannels {
 public:
  /// Forgets what was sent and held: every ghost of the next exchange travels whole.
  void reset();
  /// When false, every exchange behaves as after a reset (full records only): for comparisons.
  void setCompact(bool on) { compact_ = on; }
  /// Heap bytes of the channels and scratch (capacities, core/memory.h; map nodes not counted).
  std::uint64_t heapBytes() const;

  /// Sender: ghost copy `p` with periodic image `image` goes to `rank` in this exchange.
  void queue(int rank, const particles::Particle& p, const domain::Index3& image);
  /// Sender: the message for every rank that held or is sent ghosts or has `records`: its ghost
  /// section, then its records. The queues become what each rank now holds.
  GhostCounts pack(const std::map<int, SendBuffer>& records, std::map<int, SendBuffer>& outgoing);

  /// Receiver: reads the ghost section at the front of a message from `rank` (an empty message:
  /// nothing held, nothing new). Throws Error if the message does not fit what is held.
  GhostCounts unpack(int rank, RecvBuffer& in);
  /// The ghosts held, by source rank, each with its image: (particle, image).
  template <typename Visit>
  void forEachHeld(Visit&& visit) const {
    for (const auto& [rank, c] : channels_) {
      for (std::size_t i = 0; i < c.held.size(); ++i) visit(c.held[i], c.held_image[i]);
    }
  }

 private:
  struct Queued {
    particles::Particle p;
    domain::Index3 image;
  };
  struct Channel {
    std::vector<Queued> sent;               // what the rank holds from us, in its order
    std::vector<Queued> queued;             // this exchange's ghosts for it
    std::vector<particles::Particle> held;  // what we hold from it
    std::vector<domain::Index3> held_image;
  };
  void packChannel(Channel& c, SendBuffer& out, GhostCounts& counts);

  std::map<int, Channel> channels_;  // by rank: the sender and the receiver side
  bool compact_ = true;
  // Scratch, kept between calls.
  std::vector<std::uint32_t> order_;
  std::vector<std::uint8_t> used_, kept_;
  std::vector<Queued> next_;
};

}  // namespace polydem::comm
