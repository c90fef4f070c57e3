#include "polydem/core/exact_sum.h"

#include <cmath>
#include <limits>

namespace polydem {

namespace {
constexpr int kMinExponent = -1074;  // weight of bit 0 of digit 0
constexpr std::int64_t kDigitBase = 1LL << 32;
constexpr std::int64_t kMaxPending = 1LL << 29;  // headroom before a carry propagation
__extension__ using UInt128 = unsigned __int128;
}  // namespace

void ExactSum::add(double x) {
  if (x == 0.0) return;
  if (!std::isfinite(x)) {
    non_finite_ = true;
    return;
  }
  int exponent = 0;
  const double fraction = std::frexp(x, &exponent);  // x = fraction * 2^exponent, |f| in [.5,1)
  auto mantissa = static_cast<std::int64_t>(std::ldexp(fraction, 53));  // exact, |m| < 2^53
  int bit = exponent - 53 - kMinExponent;  // weight of the mantissa's lowest bit
  if (bit < 0) {  // subnormal: the low bits of the mantissa are zero, drop them exactly
    mantissa >>= -bit;
    bit = 0;
  }
  const bool negative = mantissa < 0;
  const UInt128 magnitude = static_cast<UInt128>(negative ? -mantissa : mantissa) << (bit % 32);
  const int k = bit / 32;
  const std::int64_t chunk[3] = {static_cast<std::int64_t>(magnitude & 0xffffffffu),
                                 static_cast<std::int64_t>((magnitude >> 32) & 0xffffffffu),
                                 static_cast<std::int64_t>(magnitude >> 64)};
  for (int i = 0; i < 3; ++i) digit_[k + i] += negative ? -chunk[i] : chunk[i];
  if (++pending_ >= kMaxPending) normalize();
}

ExactSum& ExactSum::operator+=(const ExactSum& other) {
  ExactSum rhs = other;
  rhs.normalize();
  normalize();
  for (int i = 0; i < kDigits; ++i) digit_[i] += rhs.digit_[i];
  pending_ = 2;
  non_finite_ = non_finite_ || other.non_finite_;
  return *this;
}

void ExactSum::normalize() {
  // Propagate carries so that every digit but the last lies in [0, 2^32); the last keeps the sign.
  for (int i = 0; i + 1 < kDigits; ++i) {
    const std::int64_t carry = digit_[i] >> 32;  // arithmetic shift: floor division
    digit_[i] -= carry * kDigitBase;
    digit_[i + 1] += carry;
  }
  pending_ = 0;
}

double ExactSum::value() const {
  if (non_finite_) return std::numeric_limits<double>::quiet_NaN();
  ExactSum copy = *this;
  copy.normalize();
  double sign = 1.0;
  if (copy.digit_[kDigits - 1] < 0) {  // work on the magnitude so no cancellation can occur
    for (auto& d : copy.digit_) d = -d;
    copy.normalize();
    sign = -1.0;
  }
  // The normalised digits are a canonical form of the exact value, so summing them from the most
  // significant down gives the same bits whatever order the terms were added in.
  double result = 0.0;
  for (int i = kDigits - 1; i >= 0; --i) {
    if (copy.digit_[i] != 0) {
      result += std::ldexp(static_cast<double>(copy.digit_[i]), 32 * i + kMinExponent);
    }
  }
  return sign * result;
}

void ExactSum::allreduce(MPI_Comm comm) {
  normalize();
  std::array<std::int64_t, kDigits> total{};
  MPI_Allreduce(digit_.data(), total.data(), kDigits, MPI_INT64_T, MPI_SUM, comm);
  digit_ = total;
  int flag = non_finite_ ? 1 : 0, any = 0;
  MPI_Allreduce(&flag, &any, 1, MPI_INT, MPI_LOR, comm);
  non_finite_ = any != 0;
  int ranks = 1;
  MPI_Comm_size(comm, &ranks);
  pending_ = ranks;
  normalize();
}

ExactSum::Digits ExactSum::digits() const {
  ExactSum copy = *this;
  copy.normalize();
  return copy.digit_;
}

ExactSum ExactSum::fromDigits(const Digits& digits) {
  ExactSum s;
  s.digit_ = digits;
  s.pending_ = 1;
  s.normalize();
  return s;
}

double exactSum(std::span<const double> values) {
  ExactSum sum;
  for (double v : values) sum.add(v);
  return sum.value();
}

}  // namespace polydem
