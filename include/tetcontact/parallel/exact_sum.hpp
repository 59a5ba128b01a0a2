// An exact sum of doubles, rounded once: a superaccumulator, a fixed-point integer
// wide enough for every double, in 32-bit limbs held in 64-bit words.
//
// The exact sum does not depend on the order of the additions, nor on how they are split into
// partial sums that are merged afterwards; value() rounds it to the nearest double (ties to
// even). So a sum over tets gives the same bits on one process and on any number of ranks,
// each adding its own tets and merging the others' partials. The balance's sums over tets use
// it (diagnostics/balance.hpp).
#pragma once

#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>

#include "tetcontact/parallel/lanes.hpp"

namespace tc {

class ExactSum {
 public:
  /// Limb i holds multiples of 2^(32 i + k_low); 2^k_low is below the smallest subnormal and
  /// the top limbs above the largest double times 2^31 additions.
  static constexpr int k_limbs = 70;
  static constexpr int k_low = -1088;

  inline void add(double x);
  /// Adds x[0 .. n): the same sum as n calls of add, faster where each chunk of 1,024 values
  /// lies within some twenty decades of its largest (their parts summed in SIMD lanes without
  /// error: exact_sum.cpp), in the widest lanes the processor runs or in `lanes` (scalar: add,
  /// one value at a time; wider than the processor runs: std::invalid_argument).
  struct Chunks {
    std::size_t split = 0;     // chunks summed by their parts
    std::size_t leftover = 0;  // of them, those with values below the parts, added one by one
  };
  Chunks add_all(const double* x, std::size_t n);
  Chunks add_all(const double* x, std::size_t n, Lanes lanes);
  /// Adds another sum's value exactly.
  void merge(const ExactSum& other);
  /// The sum rounded to the nearest double (ties to even); NaN or ±inf when a non-finite value
  /// was added (their own IEEE sum).
  double value() const;

  /// Plain data, for sending between ranks.
  std::array<std::int64_t, k_limbs> limbs{};
  double special = 0.0;      // the IEEE sum of the non-finite values added
  std::int64_t pending = 0;  // additions since the limbs were last carried
  /// Each addition adds less than 2^33 to a limb: carried every 2^29 of them, far from 2^63.
  static constexpr std::int64_t k_carry_every = std::int64_t{1} << 29;

 private:
  void carry();
};

// x = m 2^e with m a 53-bit integer: m 2^(e − k_low) spread over three limbs from limb
// (e − k_low) / 32, each part below 2^33 (inline: the balance adds three per tet per step).
void ExactSum::add(double x) {
  const std::uint64_t bits = std::bit_cast<std::uint64_t>(x);
  const unsigned field = static_cast<unsigned>(bits >> 52) & 0x7ffu;
  if (field == 0x7ffu) {  // infinite or NaN
    special += x;
    return;
  }
  std::uint64_t m = bits & ((std::uint64_t{1} << 52) - 1);
  int p = -1074 - k_low;  // subnormal: m 2^-1074
  if (field != 0) {
    m |= std::uint64_t{1} << 52;
    p = static_cast<int>(field) - 1075 - k_low;
  } else if (m == 0) {
    return;  // ±0
  }
  const int i = p >> 5, s = p & 31;
  const std::uint64_t lo = (m & 0xffffffffu) << s, hi = (m >> 32) << s;  // < 2^63, < 2^52
  auto a = static_cast<std::int64_t>(lo & 0xffffffffu);
  auto b = static_cast<std::int64_t>((lo >> 32) + (hi & 0xffffffffu));
  auto c = static_cast<std::int64_t>(hi >> 32);
  if (bits >> 63) a = -a, b = -b, c = -c;
  limbs[i] += a;
  limbs[i + 1] += b;
  limbs[i + 2] += c;
  if (++pending == k_carry_every) carry();
}

}  // namespace tc
