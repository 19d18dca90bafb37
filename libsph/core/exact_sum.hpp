#pragma once
// Sums of doubles that do not depend on the order of the terms: every term is added exactly into a
// fixed-point accumulator wide enough for the whole double range (a "long accumulator", Kulisch &
// Miranker 1981; the idea behind the reproducible sums of Demmel & Nguyen 2015, ReproBLAS), so any
// grouping (threads, blocks, ranks) gives the same accumulator, and value() turns it into a double
// by one fixed rule. A sum over particles is then the same however they are stored or distributed
// (fluids, whose particles are re-sorted and migrate; distribution.hpp, global_exact_sum).
//
// Representation: 72 limbs of 32 bits, limb k weighing 2^(32 k - 1140), held in 64-bit integers so
// that 2^30 terms can be added before the carries are propagated. value() is within about one
// unit in the last place of the exact sum. A non-finite term makes the sum NaN (or the infinity
// of its sign if all non-finite terms share it).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include "libsph/core/parallel.hpp"

namespace sph {

class ExactSum {
 public:
  void add(double x) {
    if (x == 0) return;
    if (!std::isfinite(x)) {
      special_ = special_ == 0 || special_ == x ? x : nan();  // NaN once two differ (or one is NaN)
      return;
    }
    int e = 0;
    const double m = std::frexp(x, &e);  // x = m 2^e, 1/2 <= |m| < 1
    const auto mantissa = static_cast<std::int64_t>(std::ldexp(m, 53));  // exact: |mantissa| < 2^53
    const int bit = e - 53 - base;  // x = mantissa 2^(bit + base), bit >= 0 for every double
    // |mantissa| shifted by the bit's offset in its limb spans at most 85 bits: three 32-bit pieces.
    const auto u = static_cast<std::uint64_t>(mantissa < 0 ? -mantissa : mantissa);
    const int offset = bit % 32;
    const std::uint64_t low = u << offset, high = offset ? u >> (64 - offset) : 0;
    const std::size_t k = static_cast<std::size_t>(bit / 32);
    const std::int64_t sign = mantissa < 0 ? -1 : 1;
    limb_[k] += sign * static_cast<std::int64_t>(low & 0xffffffffu);
    limb_[k + 1] += sign * static_cast<std::int64_t>(low >> 32);
    limb_[k + 2] += sign * static_cast<std::int64_t>(high);
    if (++pending_ == (1 << 30)) normalise();
  }
  void add(const ExactSum& other) {
    ExactSum o = other;
    o.normalise();
    normalise();
    for (std::size_t k = 0; k < limbs; ++k) limb_[k] += o.limb_[k];
    pending_ = 2;  // each limb now holds at most two terms' worth
    if (other.special_ != 0) add(other.special_);
  }
  /// The sum as a double (deterministic: a function of the exact sum only).
  double value() const {
    if (special_ != 0) return special_;
    ExactSum c = *this;
    c.normalise();
    // A negative sum is held in two's complement (a top limb of -1 over limbs near 2^32): sum its
    // magnitude and negate, so that no limb far above the sum's magnitude enters.
    const bool negative = c.limb_[limbs - 1] < 0;
    if (negative) {
      for (auto& l : c.limb_) l = -l;
      c.normalise();
    }
    double sum = 0;
    for (std::size_t k = limbs; k-- > 0;)
      if (c.limb_[k] != 0) sum += std::ldexp(double(c.limb_[k]), static_cast<int>(32 * k) + base);
    return negative ? -sum : sum;
  }
  /// The accumulator as bytes and back (messages between ranks).
  std::vector<std::byte> bytes() const {
    ExactSum c = *this;
    c.normalise();
    std::vector<std::byte> out(sizeof(c.limb_) + sizeof(double));
    std::memcpy(out.data(), c.limb_.data(), sizeof(c.limb_));
    std::memcpy(out.data() + sizeof(c.limb_), &special_, sizeof(double));
    return out;
  }
  static ExactSum from_bytes(const std::vector<std::byte>& in) {
    ExactSum s;
    std::memcpy(s.limb_.data(), in.data(), sizeof(s.limb_));
    std::memcpy(&s.special_, in.data() + sizeof(s.limb_), sizeof(double));
    s.pending_ = 1;
    return s;
  }

 private:
  static constexpr int base = -1140;  // below 2^-1074 - 53: every double's lowest bit lies above it
  static constexpr std::size_t limbs = 72;
  static double nan() { return std::numeric_limits<double>::quiet_NaN(); }
  // Carries to the next limb: every limb but the top one in [0, 2^32) afterwards (a canonical form).
  void normalise() {
    for (std::size_t k = 0; k + 1 < limbs; ++k) {
      const std::int64_t carry = limb_[k] >> 32;  // floor division by 2^32
      limb_[k] -= carry * (std::int64_t(1) << 32);
      limb_[k + 1] += carry;
    }
    pending_ = 0;
  }

  std::array<std::int64_t, limbs> limb_{};
  int pending_ = 0;
  double special_ = 0;  // the infinity or NaN met, 0 if none
};

/// Sum of term(i) for i < n, independent of the order of the terms and of the thread count.
template <class Term>
double exact_sum(std::size_t n, Term&& term) {
  constexpr std::size_t block = 4096;
  const std::size_t n_blocks = (n + block - 1) / block;
  std::vector<ExactSum> part(n_blocks);
  parallel_for(n_blocks, [&](std::size_t b) {
    for (std::size_t i = b * block; i < std::min(n, (b + 1) * block); ++i) part[b].add(double(term(i)));
  });
  ExactSum total;
  for (const auto& p : part) total.add(p);
  return total.value();
}

}  // namespace sph
