#include "tetcontact/parallel/exact_sum.hpp"

#include <bit>
#include <cmath>

namespace tc {

namespace {

// 128-bit unsigned integers (a GNU extension: declared as one, so -Wpedantic accepts it).
__extension__ using U128 = unsigned __int128;

constexpr std::int64_t k_base = std::int64_t{1} << 32;

}  // namespace

// Every limb but the top into [0, 2^32), the carries upward (floor division: negative limbs
// borrow); the top limb keeps the sign.
void ExactSum::carry() {
  for (int i = 0; i + 1 < k_limbs; ++i) {
    const std::int64_t c = limbs[i] >> 32;  // arithmetic shift: floor(limb / 2^32)
    limbs[i] -= c * k_base;
    limbs[i + 1] += c;
  }
  pending = 0;
}

void ExactSum::merge(const ExactSum& other) {
  ExactSum o = other;
  o.carry();
  carry();
  for (int i = 0; i < k_limbs; ++i) limbs[i] += o.limbs[i];
  pending = 1;  // each limb now below 2^33 in magnitude: far from overflow
  special += other.special;
}

double ExactSum::value() const {
  if (special != 0.0 || std::isnan(special)) return special;
  ExactSum n = *this;
  n.carry();
  // The sign is the top limb's; a negative total is negated limb by limb and carried again.
  const bool negative = n.limbs[k_limbs - 1] < 0;
  if (negative) {
    for (std::int64_t& l : n.limbs) l = -l;
    n.carry();
  }
  int h = k_limbs - 1;
  while (h >= 0 && n.limbs[h] == 0) --h;
  if (h < 0) return 0.0;
  // The top 96 bits T (limbs h, h − 1, h − 2; below limb 0: zeros) and whether anything
  // below them is set.
  const auto limb = [&](int i) {
    return i >= 0 ? static_cast<U128>(n.limbs[i]) : static_cast<U128>(0);
  };
  const U128 t = (limb(h) << 64) | (limb(h - 1) << 32) | limb(h - 2);
  bool sticky = false;
  for (int i = 0; i < h - 2; ++i) sticky = sticky || n.limbs[i] != 0;
  // Round T to 53 bits: to nearest, ties to even (a tie with sticky bits below is above it).
  const int bits = 128 - (static_cast<std::uint64_t>(t >> 64) != 0
                              ? std::countl_zero(static_cast<std::uint64_t>(t >> 64))
                              : 64 + std::countl_zero(static_cast<std::uint64_t>(t)));
  const int r = bits > 53 ? bits - 53 : 0;
  std::uint64_t mantissa = static_cast<std::uint64_t>(t >> r);
  if (r > 0) {
    const U128 rest = t & ((static_cast<U128>(1) << r) - 1);
    const U128 half = static_cast<U128>(1) << (r - 1);
    if (rest > half || (rest == half && (sticky || (mantissa & 1)))) ++mantissa;
  }
  // Exact: the mantissa has at most 54 bits (2^53 after rounding up) and, where the result is
  // subnormal, every bit below 2^-1074 is zero (the sum of doubles is a multiple of it).
  const double magnitude = std::ldexp(static_cast<double>(mantissa), r + 32 * (h - 2) + k_low);
  return negative ? -magnitude : magnitude;
}

}  // namespace tc
