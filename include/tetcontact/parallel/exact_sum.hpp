// An exact sum of doubles, rounded once (issue 16): a superaccumulator, a fixed-point integer
// wide enough for every double, in 32-bit limbs held in 64-bit words.
//
// The exact sum does not depend on the order of the additions, nor on how they are split into
// partial sums that are merged afterwards; value() rounds it to the nearest double (ties to
// even). So a sum over tets gives the same bits on one process and on any number of ranks,
// each adding its own tets and merging the others' partials. The balance's sums over tets use
// it (diagnostics/balance.hpp).
#pragma once

#include <array>
#include <cstdint>

namespace tc {

class ExactSum {
 public:
  /// Limb i holds multiples of 2^(32 i + k_low); 2^k_low is below the smallest subnormal and
  /// the top limbs above the largest double times 2^31 additions.
  static constexpr int k_limbs = 70;
  static constexpr int k_low = -1088;

  void add(double x);
  /// Adds another sum's value exactly.
  void merge(const ExactSum& other);
  /// The sum rounded to the nearest double (ties to even); NaN or ±inf when a non-finite value
  /// was added (their own IEEE sum).
  double value() const;

  /// Plain data, for sending between ranks.
  std::array<std::int64_t, k_limbs> limbs{};
  double special = 0.0;      // the IEEE sum of the non-finite values added
  std::int64_t pending = 0;  // additions since the limbs were last carried

 private:
  void carry();
};

}  // namespace tc
