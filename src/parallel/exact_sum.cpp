#include "tetcontact/parallel/exact_sum.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>

namespace tc {

namespace {

// 128-bit unsigned integers (a GNU extension: declared as one, so -Wpedantic accepts it).
__extension__ using U128 = unsigned __int128;

constexpr std::int64_t k_base = std::int64_t{1} << 32;

// add_all's chunk: each lane's sums hold at most k_chunk / 2 values.
constexpr std::size_t k_chunk = 1024;

// W doubles, elementwise (GCC's vector extension; W the copy's register: 2 SSE2, 4 AVX2,
// 8 AVX-512), and a mask of as many lanes.
template <int W>
struct VectorOf {
  using V __attribute__((vector_size(8 * W))) = double;
  using M __attribute__((vector_size(8 * W))) = std::int64_t;
};

// v = x[0 .. min(n, W)), zeros after (by reference: a vector return would change the ABI).
template <int W, class V>
[[gnu::always_inline]] inline void load(V& v, const double* x, std::size_t n) {
  v = V{};
  if (n >= W)
    std::memcpy(&v, x, sizeof(V));  // a plain load
  else
    std::memcpy(&v, x, n * sizeof(double));
}

// The chunk's largest magnitude and Σ (x − x): 0 when every x is finite, NaN otherwise.
struct Scan {
  double big = 0.0, nan = 0.0;
};
template <int W>
[[gnu::always_inline]] inline Scan scan_body(const double* x, std::size_t n) {
  using V = typename VectorOf<W>::V;
  V big{}, nan{};
  for (std::size_t i = 0; i < n; i += W) {
    V p;
    load<W>(p, x + i, n - i);
    const V a = p < 0.0 ? -p : p;
    big = a > big ? a : big;
    nan += p - p;
  }
  Scan s;
  for (int l = 0; l < W; ++l) s.big = std::max(s.big, big[l]), s.nan += nan[l];
  return s;
}

// x[0 .. n), n ≤ k_chunk, finite, with max |x| ≤ 2^e and −890 ≤ e ≤ 1000, split without error
// into three parts (Rump, Ogita and Oishi, "Accurate floating-point summation part I", SIAM J.
// Sci. Comput. 31 (2008), Lemma 3.2): for σ = 2^k and |p| ≤ σ,
//   q = fl(fl(σ + p) − σ),  p' = fl(p − q)  give  p = q + p',  q ∈ 2^-53 σ Z,  |p'| ≤ 2^-53 σ.
// With σ1 = 2^11 2^e ≥ 2^11 max |x| (2^11 > k_chunk / 2 + 2), each lane's sum of the q's is
// exact (every partial sum a multiple of 2^-53 σ1 below σ1 in magnitude); the p' go on to
// σ2 = 2^-42 σ1 ≥ 2^11 max |p'|, and their remainders to σ3 = 2^-42 σ2. The lanes' sums of the
// three parts go into `parts` (3 W values); what the parts leave into left[0 .. n), returning
// whether any is nonzero: the parts hold every bit down to 2^-53 σ3 = 2^(e − 126), so only a
// value below 2^(e − 73) (some 2^-72 max |x|) can leave any.
template <int W>
[[gnu::always_inline]] inline bool split_body(const double* x, std::size_t n, int e, double* parts,
                                              double* left) {
  using V = typename VectorOf<W>::V;
  const double s1 = std::ldexp(1.0, e + 11), s2 = std::ldexp(s1, -42), s3 = std::ldexp(s2, -42);
  V a1{}, a2{}, a3{};
  typename VectorOf<W>::M any{};
  for (std::size_t i = 0; i < n; i += W) {
    V p;
    load<W>(p, x + i, n - i);
    const V q1 = (s1 + p) - s1, r1 = p - q1;
    const V q2 = (s2 + r1) - s2, r2 = r1 - q2;
    const V q3 = (s3 + r2) - s3, r3 = r2 - q3;
    a1 += q1;
    a2 += q2;
    a3 += q3;
    any |= r3 != 0.0;
    if (n - i >= W)
      std::memcpy(left + i, &r3, sizeof(V));  // a plain store
    else
      std::memcpy(left + i, &r3, (n - i) * sizeof(double));
  }
  std::memcpy(parts, &a1, sizeof(V));
  std::memcpy(parts + W, &a2, sizeof(V));
  std::memcpy(parts + 2 * W, &a3, sizeof(V));
  bool left_any = false;
  for (int l = 0; l < W; ++l) left_any |= any[l] != 0;
  return left_any;
}

struct Copy {
  Scan (*scan)(const double*, std::size_t);
  bool (*split)(const double*, std::size_t, int, double*, double*);
  int width;
};
Scan scan_sse2(const double* x, std::size_t n) {
  return scan_body<2>(x, n);
}
TC_TARGET_AVX2 Scan scan_avx2(const double* x, std::size_t n) {
  return scan_body<4>(x, n);
}
TC_TARGET_AVX512 Scan scan_avx512(const double* x, std::size_t n) {
  return scan_body<8>(x, n);
}
bool split_sse2(const double* x, std::size_t n, int e, double* parts, double* left) {
  return split_body<2>(x, n, e, parts, left);
}
TC_TARGET_AVX2 bool split_avx2(const double* x, std::size_t n, int e, double* parts, double* left) {
  return split_body<4>(x, n, e, parts, left);
}
TC_TARGET_AVX512 bool split_avx512(const double* x, std::size_t n, int e, double* parts,
                                   double* left) {
  return split_body<8>(x, n, e, parts, left);
}

}  // namespace

ExactSum::Chunks ExactSum::add_all(const double* x, std::size_t n) {
  return add_all(x, n, widest_lanes());
}

ExactSum::Chunks ExactSum::add_all(const double* x, std::size_t n, Lanes lanes) {
  Chunks chunks;
  if (runnable_lanes(lanes, "the exact sums") == Lanes::scalar) {
    for (std::size_t i = 0; i < n; ++i) add(x[i]);
    return chunks;
  }
  const Copy copy = copy_for(lanes, Copy{scan_sse2, split_sse2, 2}, Copy{scan_sse2, split_sse2, 2},
                             Copy{scan_avx2, split_avx2, 4}, Copy{scan_avx512, split_avx512, 8});
  for (std::size_t begin = 0; begin < n; begin += k_chunk) {
    const std::size_t m = std::min(k_chunk, n - begin);
    const double* c = x + begin;
    const Scan sc = copy.scan(c, m);
    if (sc.big == 0.0 && sc.nan == 0.0) continue;  // zeros only
    int e = 0;
    std::frexp(sc.big, &e);                       // max |x| < 2^e
    if (sc.nan != 0.0 || e < -890 || e > 1000) {  // a non-finite value, or beyond the parts
      for (std::size_t j = 0; j < m; ++j) add(c[j]);
      continue;
    }
    double parts[24], left[k_chunk];
    const bool any_left = copy.split(c, m, e, parts, left);
    ++chunks.split;
    for (int k = 0; k < 3 * copy.width; ++k) add(parts[k]);
    if (any_left) {
      ++chunks.leftover;
      for (std::size_t j = 0; j < m; ++j)
        if (left[j] != 0.0) add(left[j]);
    }
  }
  return chunks;
}

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
