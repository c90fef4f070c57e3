// Exact, order-independent summation of doubles.
//
// Monitors such as the kinetic energy or the force ratio (Keissar eq. 3.2) are sums over all
// particles of all ranks. A plain floating-point sum depends on the order of the terms, hence on
// how particles are spread over ranks, and a stop condition "R < 1e-5" could then fire one step
// earlier on 4 ranks than on 1. ExactSum keeps the sum as a long fixed-point number (32-bit digits
// in 64-bit words, from 2^-1074 to 2^1024), so additions are integer additions: associative,
// exact, and the same bits whatever the order or the rank count. value() rounds once at the end.
#pragma once

#include <mpi.h>

#include <array>
#include <cstdint>
#include <span>

namespace polydem {

class ExactSum {
 public:
  void add(double x);
  ExactSum& operator+=(double x) {
    add(x);
    return *this;
  }
  ExactSum& operator+=(const ExactSum& other);

  /// The sum, rounded to double; NaN if any term was NaN or infinite.
  double value() const;

  /// Replaces this sum by the sum over all ranks of `comm` (collective).
  void allreduce(MPI_Comm comm);

  static constexpr int kDigits = 67;  // 67 * 32 bits cover the whole double range plus carries
  using Digits = std::array<std::int64_t, kDigits>;
  /// The exact state, normalised (for checkpoints: a restarted sum continues with the same bits).
  Digits digits() const;
  static ExactSum fromDigits(const Digits& digits);

 private:
  void normalize();

  std::array<std::int64_t, kDigits> digit_{};
  std::int64_t pending_ = 0;  // additions since the last carry propagation
  bool non_finite_ = false;
};

/// Exact sum of a range of doubles.
double exactSum(std::span<const double> values);

}  // namespace polydem
