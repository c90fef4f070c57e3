// A 64-bit hash of raw bits, used to compare final states of runs bit for bit (across rank
// counts, across a restart) from outside the program.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>

#include "polydem/core/types.h"

namespace polydem {

class BitHasher {
 public:
  void add(std::uint64_t word) {
    // multiply-xorshift mixing of 64-bit words (after the finaliser of SplitMix64)
    h_ ^= word + 0x9e3779b97f4a7c15ULL + (h_ << 6) + (h_ >> 2);
    h_ = mix(h_);
  }
  void add(double x) {
    std::uint64_t bits = 0;
    std::memcpy(&bits, &x, sizeof bits);
    add(bits);
  }
  void add(const Vec3& v) {
    for (int i = 0; i < 3; ++i) add(v[i]);
  }
  void add(const Quat& q) {
    add(q.w());
    add(q.x());
    add(q.y());
    add(q.z());
  }
  std::uint64_t value() const { return h_; }

  static std::uint64_t mix(std::uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  static std::string hex(std::uint64_t value) {
    static const char* digits = "0123456789abcdef";
    std::string out(16, '0');
    for (int i = 15; i >= 0; --i, value >>= 4) out[i] = digits[value & 0xf];
    return out;
  }

 private:
  std::uint64_t h_ = 0x6a09e667f3bcc908ULL;
};

}  // namespace polydem
