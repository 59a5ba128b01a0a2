#include "tetcontact/narrowphase/exact_ccd.hpp"
#include "tetcontact/narrowphase/coplanarity.hpp"

#include "tetcontact/narrowphase/interval_ccd.hpp"

#include <gmpxx.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <functional>
#include <type_traits>
#include <vector>

namespace tc {
namespace {

using Z = mpz_class;

// The exact path works on integers. Every double is m·2^e with an integer m, so the 24
// coordinates of a query, multiplied by one power of two, are integers; the questions asked
// (signs, roots in t) do not change under that scaling. Polynomials in t then have integer
// coefficients, and every point of [0, 1] where a sign is asked is a dyadic rational (0, 1,
// midpoints of dyadic intervals): nothing here ever needs a rational, or a gcd of numbers but
// to keep coefficients small.

// A dyadic rational k / 2^j.
struct Q {
  Z k;
  unsigned long j = 0;
  Q() = default;
  Q(long v) : k(v) {}  // NOLINT: integers convert
  Q(Z kk, unsigned long jj) : k(std::move(kk)), j(jj) {}
  double get_d() const {  // rounded toward zero, as mpq_get_d does
    long e = 0;
    const double m = mpz_get_d_2exp(&e, k.get_mpz_t());
    return std::ldexp(m, static_cast<int>(e - static_cast<long>(j)));
  }
};
Z shifted(const Q& a, unsigned long to) {  // a.k · 2^(to − a.j), to ≥ a.j
  Z r;
  mpz_mul_2exp(r.get_mpz_t(), a.k.get_mpz_t(), to - a.j);
  return r;
}
Q operator+(const Q& a, const Q& b) {
  const unsigned long j = std::max(a.j, b.j);
  return {shifted(a, j) + shifted(b, j), j};
}
Q operator-(const Q& a, const Q& b) {
  const unsigned long j = std::max(a.j, b.j);
  return {shifted(a, j) - shifted(b, j), j};
}
Q operator*(const Q& a, const Q& b) {
  return {a.k * b.k, a.j + b.j};
}
Q operator*(const Z& a, const Q& b) {
  return {a * b.k, b.j};
}
int sign(const Q& q) {
  return sgn(q.k);
}
int cmp(const Q& a, const Q& b) {
  return sign(a - b);
}
bool operator<(const Q& a, const Q& b) {
  return cmp(a, b) < 0;
}
bool operator>(const Q& a, const Q& b) {
  return cmp(a, b) > 0;
}
bool operator==(const Q& a, const Q& b) {
  return cmp(a, b) == 0;
}
Q abs(const Q& a) {
  return {::abs(a.k), a.j};
}
// (a + b)/2, in lowest terms so that repeated halving keeps the numbers short.
Q midpoint(const Q& a, const Q& b) {
  Q m = a + b;
  ++m.j;
  if (m.k == 0) return Q(0);
  const unsigned long zeros = std::min(mpz_scan1(m.k.get_mpz_t(), 0), m.j);
  mpz_fdiv_q_2exp(m.k.get_mpz_t(), m.k.get_mpz_t(), zeros);
  m.j -= zeros;
  return m;
}

// A polynomial in t with integer coefficients, c[k] the coefficient of t^k.
struct Poly {
  std::vector<Z> c;
  Poly() = default;
  explicit Poly(std::vector<Z> v) : c(std::move(v)) { trim(); }
  void trim() {
    while (!c.empty() && c.back() == 0) c.pop_back();
  }
  int degree() const { return static_cast<int>(c.size()) - 1; }  // −1 for the zero polynomial
  int terms() const { return static_cast<int>(c.size()); }
  bool zero() const { return c.empty(); }
  Q operator()(const Q& t) const {  // exact, by Horner
    Q r(0);
    for (std::size_t k = c.size(); k-- > 0;) r = r * t + Q(c[k], 0);
    return r;
  }
};

// Sign of p at the dyadic t = k / 2^j without forming the value: by Horner on integers,
//   2^(j n) p(k / 2^j) = Σ c_i k^i 2^(j (n − i)),  R_n = c_n,  R_i = R_(i+1) k + c_i 2^(j (n − i)),
// in storage kept per thread (the exact path spends most of its time in these signs; a
// value built from temporaries allocates at every operation).
// 2^(j n) p(k / 2^j) into r (storage kept per thread by the callers).
void scaled_value(const Poly& p, const Q& t, Z& r) {
  thread_local Z s;
  const int n = p.degree();
  r = p.c[n];
  for (int i = n - 1; i >= 0; --i) {
    mpz_mul(r.get_mpz_t(), r.get_mpz_t(), t.k.get_mpz_t());
    mpz_mul_2exp(s.get_mpz_t(), p.c[i].get_mpz_t(), t.j * static_cast<unsigned long>(n - i));
    mpz_add(r.get_mpz_t(), r.get_mpz_t(), s.get_mpz_t());
  }
}
int sign_of(const Poly& p, const Q& t) {
  if (p.zero()) return 0;
  thread_local Z r;
  scaled_value(p, t, r);
  return sgn(r);
}

Poly operator+(const Poly& a, const Poly& b) {
  std::vector<Z> r(std::max(a.c.size(), b.c.size()));
  for (std::size_t k = 0; k < a.c.size(); ++k) r[k] += a.c[k];
  for (std::size_t k = 0; k < b.c.size(); ++k) r[k] += b.c[k];
  return Poly(std::move(r));
}
Poly operator-(const Poly& a, const Poly& b) {
  std::vector<Z> r(std::max(a.c.size(), b.c.size()));
  for (std::size_t k = 0; k < a.c.size(); ++k) r[k] += a.c[k];
  for (std::size_t k = 0; k < b.c.size(); ++k) r[k] -= b.c[k];
  return Poly(std::move(r));
}
Poly operator*(const Poly& a, const Poly& b) {
  if (a.zero() || b.zero()) return Poly();
  std::vector<Z> r(a.c.size() + b.c.size() - 1);
  for (std::size_t i = 0; i < a.c.size(); ++i)
    for (std::size_t j = 0; j < b.c.size(); ++j)
      mpz_addmul(r[i + j].get_mpz_t(), a.c[i].get_mpz_t(), b.c[j].get_mpz_t());
  return Poly(std::move(r));
}
Poly derivative(const Poly& a) {
  std::vector<Z> r;
  for (std::size_t k = 1; k < a.c.size(); ++k) r.push_back(a.c[k] * static_cast<long>(k));
  return Poly(std::move(r));
}
// a divided by the gcd of its coefficients (a positive number: signs and roots unchanged).
Poly primitive(Poly a) {
  Z g = 0;
  for (const Z& x : a.c) mpz_gcd(g.get_mpz_t(), g.get_mpz_t(), x.get_mpz_t());
  if (g > 1)
    for (Z& x : a.c) mpz_divexact(x.get_mpz_t(), x.get_mpz_t(), g.get_mpz_t());
  return a;
}
// Pseudo-division by b ≠ 0 with positive multipliers only: each step
//   a ← |lc b| a − sgn(lc b) lc(a) t^s b,   q ← |lc b| q + sgn(lc b) lc(a) t^s,
// keeps |lc b|^m a₀ = q b + a, so the remainder and the quotient come out as positive multiples
// of the true ones (what Sturm sequences, gcds and square-free parts need).
void pseudo_divide(Poly& a, const Poly& b, Poly* q) {
  const Z lb = ::abs(b.c.back());
  const int sb = sgn(b.c.back());
  if (q) q->c.assign(std::max(0, a.degree() - b.degree() + 1), Z(0));
  while (!a.zero() && a.degree() >= b.degree()) {
    const Z f = sb * a.c.back();
    const int shift = a.degree() - b.degree();
    for (Z& x : a.c) x *= lb;
    for (std::size_t k = 0; k < b.c.size(); ++k) a.c[k + shift] -= f * b.c[k];
    a.c.back() = 0;  // exact cancellation of the leading term
    a.trim();
    if (q) {
      for (Z& x : q->c) x *= lb;
      q->c[shift] += f;
    }
  }
  if (q) q->trim();
}
Poly remainder(Poly a, const Poly& b) {  // a positive multiple of a mod b
  pseudo_divide(a, b, nullptr);
  return primitive(std::move(a));
}
Poly quotient(Poly a, const Poly& b) {  // a positive multiple of a / b, when b divides a
  Poly q;
  pseudo_divide(a, b, &q);
  return primitive(std::move(q));
}
Poly gcd(Poly a, Poly b) {
  while (!b.zero()) {
    Poly r = remainder(a, b);
    a = std::move(b);
    b = std::move(r);
  }
  return primitive(std::move(a));
}

// Number of distinct real roots in (lo, hi] of a square-free p, from its Sturm sequence.
int sturm_count(const std::vector<Poly>& seq, const Q& lo, const Q& hi) {
  const auto changes = [&](const Q& t) {
    int n = 0, last = 0;
    for (const Poly& p : seq) {
      const int s = sign_of(p, t);
      if (s == 0) continue;
      if (last != 0 && s != last) ++n;
      last = s;
    }
    return n;
  };
  return changes(lo) - changes(hi);
}
std::vector<Poly> sturm_sequence(const Poly& p) {
  std::vector<Poly> seq{p, derivative(p)};
  while (!seq.back().zero() && seq.back().degree() > 0) {
    Poly r = remainder(seq[seq.size() - 2], seq.back());
    for (Z& x : r.c) x = -x;
    if (r.zero()) break;
    seq.push_back(r);
  }
  return seq;
}

// A point of [0, 1] where signs are asked: a rational, or the single root of a square-free q in
// the open interval (lo, hi).
struct Point {
  bool rational = true;
  Q t;
  Poly q;
  Q lo, hi;
  bool narrowed = false;  // narrow() has run on it
};

// Halves an irrational point's interval, keeping its root; if the root turns out to be
// the rational midpoint, the point becomes rational.
void bisect(Point& pt) {
  const Q mid = midpoint(pt.lo, pt.hi);
  const int sm = sign_of(pt.q, mid);
  if (sm == 0) {
    pt.rational = true;
    pt.t = mid;
  } else if (sm == sign_of(pt.q, pt.lo)) {
    pt.lo = mid;
  } else {
    pt.hi = mid;
  }
}

// A double as a dyadic rational, exactly (x ≥ 0).
Q dyadic(double x) {
  if (x == 0.0) return Q(0);
  int e = 0;
  const double m = std::frexp(x, &e);  // x = m 2^e, 0.5 ≤ m < 1
  Z k(static_cast<long>(std::ldexp(m, 53)));
  const long j = 53L - e;
  if (j >= 0) return Q(k, static_cast<unsigned long>(j));
  mpz_mul_2exp(k.get_mpz_t(), k.get_mpz_t(), static_cast<unsigned long>(-j));
  return Q(k, 0);
}

// Narrows an irrational point's interval to two neighbouring doubles where it can, guided by
// floating point and decided exactly: the root is found by bisection in doubles on the
// polynomial scaled to doubles (a guess: rounding may put it a few ulps off), and the guess
// [a, b] is kept only when q's exact signs at a and b enclose the root (each a dyadic rational,
// two exact evaluations instead of the fifty or so halvings of the interval that reaching
// double resolution takes). Tries [a, b] widened by 2⁴ and 2⁸ ulps before giving up; the
// interval then stays as it was. Returns true when the root rounds down to the interval's lower
// end as a double: the ends are neighbouring doubles or round down to the same one (or the
// point became rational).
bool narrow(Point& pt) {
  if (pt.rational) return true;
  pt.narrowed = true;
  if (pt.lo.get_d() == pt.hi.get_d()) return true;  // narrowed already: the root rounds to it
  const int n = pt.q.degree();
  long top = 0;
  std::array<double, 8> c{};
  std::array<long, 8> e{};
  if (n < 1 || n >= 8) return false;
  for (int k = 0; k <= n; ++k) {
    c[k] = mpz_get_d_2exp(&e[k], pt.q.c[k].get_mpz_t());
    top = k == 0 ? e[k] : std::max(top, e[k]);
  }
  for (int k = 0; k <= n; ++k)
    c[k] = std::ldexp(c[k], static_cast<int>(std::max(e[k] - top, -1100L)));
  const auto value = [&](double t) {
    double r = c[n];
    for (int k = n - 1; k >= 0; --k) r = r * t + c[k];
    return r;
  };
  const int s_lo = sign_of(pt.q, pt.lo);  // nonzero: the root is inside (lo, hi)
  if (s_lo == 0) return false;
  double a = pt.lo.get_d(), b = std::nextafter(pt.hi.get_d(), 2.0);
  while (std::nextafter(a, 2.0) < b) {
    const double m = a + 0.5 * (b - a);
    if (m <= a || m >= b) break;
    const double v = value(m);
    if ((v > 0) == (s_lo > 0) && v != 0)
      a = m;
    else
      b = m;
  }
  for (const double widen : {0.0, 16.0, 256.0}) {
    double lo = a, hi = b;
    for (int k = 0; k < widen; ++k) lo = std::nextafter(lo, -1.0), hi = std::nextafter(hi, 2.0);
    Q qlo = dyadic(std::max(lo, 0.0)), qhi = dyadic(std::min(hi, 1.0));
    const bool inside = pt.lo < qlo && qhi < pt.hi;  // else clamped to the interval
    if (!(pt.lo < qlo)) qlo = pt.lo;
    if (!(qhi < pt.hi)) qhi = pt.hi;
    const int sl = sign_of(pt.q, qlo), sh = sign_of(pt.q, qhi);
    if (sl == 0 || sh == 0) {  // a rational root, the point's own (it is the only one inside)
      pt.rational = true;
      pt.t = sl == 0 ? qlo : qhi;
      return true;
    }
    if (sl == s_lo && sh == -s_lo) {
      pt.lo = qlo;
      pt.hi = qhi;
      return widen == 0.0 && inside;
    }
  }
  return false;
}

// L = Σ k |c_k| ≥ max |g'| on [0, 1]: on [lo, hi] ⊂ [0, 1], |g(lo)| > (hi − lo) L means g has
// no root there and keeps g(lo)'s sign.
Z slope_bound(const Poly& g) {
  Z lip = 0;
  for (std::size_t k = 1; k < g.c.size(); ++k) lip += static_cast<long>(k) * ::abs(g.c[k]);
  return lip;
}

// Sign of g at the point, exactly.
// The sign of g at lo when |g(lo)| > (hi − lo) L, else 0. On integers, with lo = k / 2^j and
// hi − lo = w / 2^i: |2^(j n) g(lo)| 2^i > L w 2^(j n).
int lipschitz_sign(const Poly& g, const Z& lip, const Q& lo, const Q& hi) {
  thread_local Z value, width, left, right;
  scaled_value(g, lo, value);
  if (sgn(value) == 0) return 0;
  const unsigned long i = std::max(lo.j, hi.j);
  mpz_mul_2exp(width.get_mpz_t(), hi.k.get_mpz_t(), i - hi.j);
  mpz_mul_2exp(left.get_mpz_t(), lo.k.get_mpz_t(), i - lo.j);
  mpz_sub(width.get_mpz_t(), width.get_mpz_t(), left.get_mpz_t());
  mpz_abs(left.get_mpz_t(), value.get_mpz_t());
  mpz_mul_2exp(left.get_mpz_t(), left.get_mpz_t(), i);
  mpz_mul(right.get_mpz_t(), lip.get_mpz_t(), width.get_mpz_t());
  mpz_mul_2exp(right.get_mpz_t(), right.get_mpz_t(), lo.j * static_cast<unsigned long>(g.degree()));
  return mpz_cmp(left.get_mpz_t(), right.get_mpz_t()) > 0 ? sgn(value) : 0;
}

// The shortcuts in front of the plain exact arithmetic: fixed-width integers and the signs at a
// root certified in doubles (set_exact_ccd_shortcuts).
std::atomic<bool> shortcuts{true};
bool shortcuts_on() {
  return shortcuts.load(std::memory_order_relaxed);
}

// Doubles a ≤ b that enclose the point (after narrow(), an irrational root's ends are
// neighbouring doubles or close to it): get_d truncates, so it gives a lower end, and the next
// double above an upper end's is above it (within half an ulp in the subnormal range, where
// get_d's last step rounds to nearest; a lower end there is taken as 0).
std::pair<double, double> enclosing(const Point& pt) {
  const Q& lo = pt.rational ? pt.t : pt.lo;
  const Q& hi = pt.rational ? pt.t : pt.hi;
  const double a = lo.get_d();
  return {a < 0x1p-1000 ? 0.0 : a, std::nextafter(hi.get_d(), 2.0)};
}

// Certified sign of a polynomial at every t in [a, b], 0 ≤ a, t ≤ 1 (b may pass 1 by an ulp),
// from its coefficients as doubles, c[k] for t^k, each within 2⁻⁵¹ of the true one relatively
// (0: undecided). With P the polynomial of the rounded coefficients, S = Σ |c_k| a^k and
// L = Σ k |c_k|:
//   |p(t) − fl(P(a))| ≤ |p(a) − P(a)| + |P(a) − fl(P(a))| + |p(t) − p(a)|
//                    ≤ 2⁻⁵¹ S + γ₂ₙ S + (b − a) L,
// with γ₂ₙ ≤ 2⁻⁴⁹ for the degrees here; we use 2⁻⁴⁵ S (the rounding of S itself included) and
// (1 + 2⁻⁴⁰)(b − a) L, plus 2⁻⁹⁰⁰ for coefficients scaled below the normal range.
int float_sign(const std::array<double, 8>& c, int n, double a, double b) {
  if (n == 0) return 0;
  double v = c[n - 1], s = std::abs(c[n - 1]), lip = 0.0;
  for (int k = n - 2; k >= 0; --k) {
    v = v * a + c[k];
    s = s * a + std::abs(c[k]);
  }
  for (int k = 1; k < n; ++k) lip += k * std::abs(c[k]);
  const double err = 0x1p-45 * s + (1 + 0x1p-40) * (b - a) * lip + 0x1p-900;
  return v > err ? 1 : (v < -err ? -1 : 0);
}

// Sign of g at the point, exactly, on integers. A rational point gets g's value. On an
// irrational one's [lo, hi] ⊂ [0, 1], |g(x) − g(lo)| ≤ (hi − lo) L with L = Σ k |c_k| ≥ max |g'|,
// so |g(lo)| > (hi − lo) L gives the sign; the root is narrowed to double resolution (once per
// point) and then its interval halved until the test decides. That ends unless g vanishes at
// the root: after a few halvings a gcd with q tells (q is square-free with one root in
// (lo, hi), so a common factor with a sign change there vanishes at it), and if not, halving
// goes on until the test decides.
int exact_sign_at(const Poly& g, Point& pt) {
  if (g.zero()) return 0;
  if (pt.rational) return sign_of(g, pt.t);
  const Z lip = slope_bound(g);
  bool shared_checked = false;
  for (int it = 0;; ++it) {
    if (pt.rational) return sign_of(g, pt.t);
    if (const int s = lipschitz_sign(g, lip, pt.lo, pt.hi)) return s;
    if (!pt.narrowed) {  // once per point: to double resolution by a guess checked exactly
      narrow(pt);
      continue;
    }
    if (it >= 24 && !shared_checked) {
      const Poly h = gcd(pt.q, g);
      if (h.degree() >= 1 && sign_of(h, pt.lo) * sign_of(h, pt.hi) < 0) return 0;
      shared_checked = true;
    }
    bisect(pt);
  }
}

// The real roots of p (not identically zero) in [0, 1], as points.
std::vector<Point> roots_in_unit(const Poly& p) {
  std::vector<Point> out;
  if (p.degree() < 1) return out;
  const Poly sf = quotient(p, gcd(p, derivative(p)));  // square-free part
  for (const Q& end : {Q(0), Q(1)})
    if (sign_of(sf, end) == 0) out.push_back(Point{true, end, {}, {}, {}});
  const std::vector<Poly> seq = sturm_sequence(sf);
  // Isolate the roots in the open interval (0, 1) by bisection on Sturm counts.
  std::vector<std::pair<Q, Q>> todo{{Q(0), Q(1)}};
  while (!todo.empty()) {
    auto [lo, hi] = todo.back();
    todo.pop_back();
    int n = sturm_count(seq, lo, hi);
    if (sign_of(sf, hi) == 0) --n;  // (lo, hi] counted a root at hi: an endpoint, handled apart
    if (n <= 0) continue;
    const int slo = sign_of(sf, lo), shi = sign_of(sf, hi);
    if (n == 1 && slo != 0 && shi != 0 && slo != shi) {
      out.push_back(Point{false, {}, sf, lo, hi});
      continue;
    }
    const Q mid = midpoint(lo, hi);
    if (sign_of(sf, mid) == 0) out.push_back(Point{true, mid, {}, {}, {}});
    todo.push_back({lo, mid});
    todo.push_back({mid, hi});
  }
  return out;
}

// A signed integer of 64 W bits in two's complement, W 64-bit words, least significant first.
// Sums, differences and products are taken modulo 2^(64 W), which is the exact result whenever
// it fits in 64 W − 1 bits and a sign; the queries that use it are bounded so that every value
// does (fixed_words below). No allocation: the constructions of the exact path (the moving
// points, their differences, cross and dot products, the static predicates) run on it, and only
// a sign that doubles cannot certify turns a polynomial into GMP integers.
__extension__ using Wide = unsigned __int128;
template <int W>
struct Fixed {
  static constexpr int kWords = W;
  std::array<std::uint64_t, W> w{};
  bool negative() const { return static_cast<std::int64_t>(w[W - 1]) < 0; }
  bool zero() const {
    for (const std::uint64_t x : w)
      if (x) return false;
    return true;
  }
};
template <int W>
Fixed<W> operator+(const Fixed<W>& a, const Fixed<W>& b) {
  Fixed<W> r;
  Wide carry = 0;
  for (int k = 0; k < W; ++k) {
    carry += static_cast<Wide>(a.w[k]) + b.w[k];
    r.w[k] = static_cast<std::uint64_t>(carry);
    carry >>= 64;
  }
  return r;
}
template <int W>
Fixed<W> operator-(const Fixed<W>& a, const Fixed<W>& b) {
  Fixed<W> r;
  std::uint64_t borrow = 0;
  for (int k = 0; k < W; ++k) {
    const std::uint64_t d = a.w[k] - b.w[k];
    r.w[k] = d - borrow;
    borrow = (a.w[k] < b.w[k]) | (d < borrow);
  }
  return r;
}
template <int W>
Fixed<W> operator-(const Fixed<W>& a) {
  return Fixed<W>{} - a;
}
// On the magnitudes, over their nonzero words only (most values use two to four).
template <int W>
Fixed<W> operator*(const Fixed<W>& a, const Fixed<W>& b) {
  const bool na = a.negative(), nb = b.negative();
  const Fixed<W> x = na ? -a : a, y = nb ? -b : b;
  int lx = W, ly = W;
  while (lx > 0 && x.w[lx - 1] == 0) --lx;
  while (ly > 0 && y.w[ly - 1] == 0) --ly;
  Fixed<W> r;
  for (int i = 0; i < lx; ++i) {
    Wide carry = 0;
    for (int j = 0; j < ly && i + j < W; ++j) {
      carry += static_cast<Wide>(x.w[i]) * y.w[j] + r.w[i + j];
      r.w[i + j] = static_cast<std::uint64_t>(carry);
      carry >>= 64;
    }
    if (i + ly < W) r.w[i + ly] = static_cast<std::uint64_t>(carry);
  }
  return na != nb ? -r : r;
}
template <int W>
int sgn(const Fixed<W>& a) {
  return a.negative() ? -1 : (a.zero() ? 0 : 1);
}
template <int W>
bool operator==(const Fixed<W>& a, int zero) {  // only a == 0 is asked
  return zero == 0 && a.zero();
}
// As a GMP integer.
template <int W>
Z to_z(const Fixed<W>& a) {
  const Fixed<W> m = a.negative() ? -a : a;
  Z r;
  mpz_import(r.get_mpz_t(), W, -1, sizeof(std::uint64_t), 0, 0, m.w.data());
  if (a.negative()) r = -r;
  return r;
}
// As d · 2^e with a double d carrying the top two words (within 2⁻⁵² relatively).
template <int W>
double to_d_2exp(const Fixed<W>& a, long& e) {
  const Fixed<W> m = a.negative() ? -a : a;
  int h = W - 1;
  while (h > 0 && m.w[h] == 0) --h;
  e = h == 0 ? 0 : 64L * (h - 1);
  const double d =
      h == 0 ? static_cast<double>(m.w[0])
             : std::ldexp(static_cast<double>(m.w[h]), 64) + static_cast<double>(m.w[h - 1]);
  return a.negative() ? -d : d;
}

// A polynomial in t of degree ≤ 4 on Fixed coefficients, c[k] for t^k (n of them, not trimmed).
template <int W>
struct FPoly {
  static constexpr int kWords = W;
  std::array<Fixed<W>, 5> c{};
  int n = 0;
  int terms() const { return n; }
  bool zero() const {
    for (int k = 0; k < n; ++k)
      if (!c[k].zero()) return false;
    return true;
  }
};
template <int W>
FPoly<W> operator+(const FPoly<W>& a, const FPoly<W>& b) {
  FPoly<W> r;
  r.n = std::max(a.n, b.n);
  for (int k = 0; k < r.n; ++k)
    r.c[k] = (k < a.n ? a.c[k] : Fixed<W>{}) + (k < b.n ? b.c[k] : Fixed<W>{});
  return r;
}
template <int W>
FPoly<W> operator-(const FPoly<W>& a, const FPoly<W>& b) {
  FPoly<W> r;
  r.n = std::max(a.n, b.n);
  for (int k = 0; k < r.n; ++k)
    r.c[k] = (k < a.n ? a.c[k] : Fixed<W>{}) - (k < b.n ? b.c[k] : Fixed<W>{});
  return r;
}
template <int W>
FPoly<W> operator*(const FPoly<W>& a, const FPoly<W>& b) {  // degrees add up to ≤ 4 here
  FPoly<W> r;
  if (a.n == 0 || b.n == 0) return r;
  r.n = a.n + b.n - 1;
  for (int i = 0; i < a.n; ++i)
    for (int j = 0; j < b.n; ++j) r.c[i + j] = r.c[i + j] + a.c[i] * b.c[j];
  return r;
}
const Poly& to_poly(const Poly& p) {
  return p;
}
template <int W>
Poly to_poly(const FPoly<W>& p) {
  std::vector<Z> c(p.n);
  for (int k = 0; k < p.n; ++k) c[k] = to_z(p.c[k]);
  return Poly(std::move(c));
}
double to_d_2exp(const Z& a, long& e) {  // truncated: within 2⁻⁵² relatively
  return mpz_get_d_2exp(&e, a.get_mpz_t());
}
// The coefficients of g (P = Poly or FPoly) as doubles, all scaled by one power of two so that
// the largest is below 1 and above 1/4: 0 terms for the zero polynomial or a degree beyond 7.
template <class P>
int scaled_doubles(const P& g, std::array<double, 8>& c) {
  const int n = g.terms();
  if (n > 8) return 0;
  std::array<long, 8> e{};
  long top = 0;
  bool any = false;
  for (int k = 0; k < n; ++k) {
    c[k] = to_d_2exp(g.c[k], e[k]);
    if (c[k] != 0.0) {
      int ek = 0;
      std::frexp(c[k], &ek);
      top = any ? std::max(top, e[k] + ek) : e[k] + ek;
      any = true;
    }
  }
  if (!any) return 0;
  for (int k = 0; k < n; ++k)
    c[k] = c[k] == 0.0 ? 0.0 : std::ldexp(c[k], static_cast<int>(std::max(e[k] - top, -1100L)));
  return n;
}
// Sign of g at the point: with the shortcuts on, the point narrowed first (once per point: every
// sign at a root shares it) and the certified sign in doubles tried before the exact one on GMP
// integers.
template <class P>
int sign_at(const P& g, Point& pt) {
  if (g.zero()) return 0;
  if (!shortcuts_on()) return exact_sign_at(to_poly(g), pt);
  if (!pt.narrowed) narrow(pt);
  std::array<double, 8> c{};
  const auto [a, b] = enclosing(pt);
  if (const int s = float_sign(c, scaled_doubles(g, c), a, b)) return s;
  return exact_sign_at(to_poly(g), pt);
}

// Polynomial vectors: a point moving linearly, x(t) = x0 + t (x1 − x0), on Fixed or on GMP
// coefficients (P = FPoly or Poly).
template <class P>
using PV = std::array<P, 3>;
// The least and largest exponents e of the query's nonzero coordinates x = m 2^e,
// 0.5 ≤ |m| < 1 (both 0 when every coordinate is 0).
std::pair<int, int> exponent_range(const std::array<Vec3, 8>& q) {
  int lo = 0, hi = 0;
  bool any = false;
  for (const Vec3& x : q)
    for (int d = 0; d < 3; ++d) {
      if (x[d] == 0.0) continue;
      int e = 0;
      std::frexp(x[d], &e);
      lo = any ? std::min(lo, e) : e;
      hi = any ? std::max(hi, e) : e;
      any = true;
    }
  return {lo, hi};
}
// The power of two that makes every coordinate of the query an integer: the least exponent of
// a last mantissa bit, 2^(e − 53).
long integer_exponent(const std::array<Vec3, 8>& q) {
  return static_cast<long>(exponent_range(q).first) - 53;
}
// The words of the narrowest Fixed that holds the query exactly (4, 6 or 8), or 0 when none
// does. Its coordinates as integers are below 2^B, B = 53 + (largest − least exponent); a
// difference of two moving points has Σ|coefficients| < 2^(B+3), a cross product of two
// < 2^(2B+7), the dot product of two cross products (the largest value formed, degree 4)
// < 2^(4B+16), and every value on the way is bounded alike: W words hold them when
// 4B + 16 ≤ 64 W − 1, exponents spread over at most 6, 38 or 70 binary orders.
int fixed_words(const std::array<Vec3, 8>& q) {
  const auto [lo, hi] = exponent_range(q);
  const int B = 53 + (hi - lo);
  for (const int W : {4, 6, 8})
    if (4 * B + 16 <= 64 * W - 1) return W;
  return 0;
}
// x · 2^(−E), an integer when E ≤ the exponent of x's last mantissa bit.
Z integer(double x, long E) {
  if (x == 0.0) return Z(0);
  int e = 0;
  const double m = std::frexp(x, &e);
  Z r(static_cast<long>(std::ldexp(m, 53)));  // exact: 53 bits
  mpz_mul_2exp(r.get_mpz_t(), r.get_mpz_t(), static_cast<unsigned long>(e - 53 - E));
  return r;
}
// The same as a Fixed integer: the mantissa shifted by e − 53 − E, at most the spread of the
// exponents (≤ 70 by fixed_words), so it spans two words at most.
template <int W>
Fixed<W> fixed_integer(double x, long E) {
  Fixed<W> r;
  if (x == 0.0) return r;
  int e = 0;
  const double m = std::frexp(x, &e);
  const auto mag = static_cast<std::uint64_t>(std::ldexp(std::abs(m), 53));
  const long shift = e - 53 - E;
  const int word = static_cast<int>(shift / 64), bit = static_cast<int>(shift % 64);
  r.w[word] = mag << bit;
  if (bit > 11) r.w[word + 1] = mag >> (64 - bit);
  return m < 0 ? -r : r;
}
template <class P>
P linear(const double x0, const double x1, long E) {
  if constexpr (std::is_same_v<P, Poly>) {
    const Z a = integer(x0, E);
    return Poly({a, integer(x1, E) - a});
  } else {
    P p;
    p.n = 2;
    p.c[0] = fixed_integer<P::kWords>(x0, E);
    p.c[1] = fixed_integer<P::kWords>(x1, E) - p.c[0];
    return p;
  }
}
template <class P>
PV<P> moving(const Vec3& x0, const Vec3& x1, long E) {
  return {linear<P>(x0[0], x1[0], E), linear<P>(x0[1], x1[1], E), linear<P>(x0[2], x1[2], E)};
}
template <class P>
PV<P> sub(const PV<P>& a, const PV<P>& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
template <class P>
PV<P> cross(const PV<P>& a, const PV<P>& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
template <class P>
P dot(const PV<P>& a, const PV<P>& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
template <class P>
bool is_zero_at(const PV<P>& v, Point& pt) {
  return sign_at(v[0], pt) == 0 && sign_at(v[1], pt) == 0 && sign_at(v[2], pt) == 0;
}

// p on the closed segment [a, b] at the point (collinearity and betweenness; a = b: p = a).
template <class P>
bool on_segment(const PV<P>& p, const PV<P>& a, const PV<P>& b, Point& pt) {
  const PV<P> ab = sub(b, a), ap = sub(p, a);
  if (is_zero_at(ab, pt)) return is_zero_at(ap, pt);
  if (!is_zero_at(cross(ab, ap), pt)) return false;
  return sign_at(dot(ap, ab), pt) >= 0 && sign_at(dot(sub(p, b), sub(a, b)), pt) >= 0;
}

// Coplanar closed segments [a, b] and [c, d] meet at the point.
template <class P>
bool segments_meet(const PV<P>& a, const PV<P>& b, const PV<P>& c, const PV<P>& d, Point& pt) {
  const PV<P> u = sub(b, a), v = sub(d, c);
  const PV<P> m = cross(u, v);
  if (!is_zero_at(m, pt)) {  // not parallel: proper orientation tests in the plane
    const int o1 = sign_at(dot(cross(u, sub(c, a)), m), pt);
    const int o2 = sign_at(dot(cross(u, sub(d, a)), m), pt);
    if (o1 * o2 > 0) return false;
    const int o3 = sign_at(dot(cross(v, sub(a, c)), m), pt);
    const int o4 = sign_at(dot(cross(v, sub(b, c)), m), pt);
    return o3 * o4 <= 0;
  }
  // Parallel, collinear or degenerate: some endpoint lies on the other segment.
  return on_segment(a, c, d, pt) || on_segment(b, c, d, pt) || on_segment(c, a, b, pt) ||
         on_segment(d, a, b, pt);
}

// Coplanar point p in the closed triangle (a, b, c) at the point.
template <class P>
bool point_in_triangle(const PV<P>& p, const PV<P>& a, const PV<P>& b, const PV<P>& c, Point& pt) {
  const PV<P> n = cross(sub(b, a), sub(c, a));
  if (is_zero_at(n, pt))  // degenerate triangle: a segment or a point
    return on_segment(p, a, b, pt) || on_segment(p, b, c, pt) || on_segment(p, c, a, pt);
  return sign_at(dot(cross(sub(b, a), sub(p, a)), n), pt) >= 0 &&
         sign_at(dot(cross(sub(c, b), sub(p, b)), n), pt) >= 0 &&
         sign_at(dot(cross(sub(a, c), sub(p, c)), n), pt) >= 0;
}

// The time of a point as a double: a rational's nearest-below double, an irrational root's
// interval refined until both ends round to the same double (its lower end is returned).
double time_of(Point pt) {
  // Between neighbouring doubles a < root < b, the root rounds down to a: the lower end.
  if (narrow(pt) && !pt.rational) return pt.lo.get_d();
  for (int i = 0; i < 2000 && !pt.rational && pt.lo.get_d() != pt.hi.get_d(); ++i) bisect(pt);
  return pt.rational ? pt.t.get_d() : pt.lo.get_d();
}

// A sort key that orders isolated roots: rationals by value, irrational roots by their interval
// (isolating intervals are disjoint and hold no other root, so the midpoint orders them).
Q key(const Point& pt) {
  return pt.rational ? pt.t : midpoint(pt.lo, pt.hi);
}

// ∃ t ∈ [0, 1]: coplanar(t) ∧ test(t). `polys` are the polynomials the test's signs depend on
// (their roots split [0, 1] where the coplanarity holds identically). Returns a time where the
// test holds, or −1; with `earliest`, the earliest such time (the set of such times is closed,
// so it has a least element), otherwise the first one found.
double exists(const Poly& coplanar, const std::vector<Poly>& polys,
              const std::function<bool(Point&)>& test, bool earliest) {
  if (!coplanar.zero()) {
    std::vector<Point> roots = roots_in_unit(coplanar);
    if (earliest)
      std::sort(roots.begin(), roots.end(),
                [](const Point& a, const Point& b) { return key(a) < key(b); });
    for (Point& pt : roots)
      if (test(pt)) return earliest ? time_of(pt) : 0.0;
    return -1.0;
  }
  // Coplanar all step: the test's outcome is constant between consecutive roots of its
  // polynomials. Each irrational root's interval is shrunk until no other polynomial has a
  // root in it (but the root itself), so that its rational ends lie in the neighbouring
  // intervals; then every root, every cut and a point between consecutive cuts is tried. The
  // set of hits is closed, so an open interval of hits has a hit at its left cut: the earliest
  // hit is among the roots and the cuts.
  std::vector<Poly> squarefree;
  for (const Poly& g : polys)
    if (g.degree() >= 1) squarefree.push_back(quotient(g, gcd(g, derivative(g))));
  std::vector<Point> pts;
  for (const Poly& g : squarefree)
    for (Point& r : roots_in_unit(g)) pts.push_back(r);
  std::vector<std::vector<Poly>> sequences;  // Sturm sequences, computed once
  std::vector<Z> slopes;
  for (const Poly& g : squarefree) {
    sequences.push_back(sturm_sequence(g));
    slopes.push_back(slope_bound(g));
  }
  for (Point& r : pts) {
    if (r.rational) continue;
    std::vector<Poly> common;  // gcd(r.q, g) per polynomial, computed once
    for (const Poly& g : squarefree) common.push_back(gcd(r.q, g));
    while (!r.rational) {
      bool clean = true;
      for (std::size_t n = 0; n < squarefree.size(); ++n) {
        const Poly& g = squarefree[n];
        const Q glo = g(r.lo);
        if (sign(glo) == 0 || sign_of(g, r.hi) == 0) {
          clean = false;
          break;
        }
        if (abs(glo) > slopes[n] * (r.hi - r.lo)) continue;  // no root of g in it at all
        const int inside = sturm_count(sequences[n], r.lo, r.hi);
        const Poly& h = common[n];
        const bool shares = h.degree() >= 1 && sign_of(h, r.lo) * sign_of(h, r.hi) < 0;
        if (inside > (shares ? 1 : 0)) {
          clean = false;
          break;
        }
      }
      if (clean) break;
      bisect(r);
    }
  }
  std::vector<Q> cuts{Q(0), Q(1)};
  for (Point& r : pts) {
    if (r.rational) {
      cuts.push_back(r.t);
    } else {
      cuts.push_back(r.lo);
      cuts.push_back(r.hi);
    }
  }
  double best = -1.0;
  const auto hit = [&](Point& p) {
    if (!test(p)) return false;
    const double t = earliest ? time_of(p) : 0.0;
    if (best < 0.0 || t < best) best = t;
    return !earliest;  // stop at the first hit unless the earliest is asked
  };
  for (Point& r : pts)
    if (hit(r)) return best;
  std::sort(cuts.begin(), cuts.end());
  cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());
  for (std::size_t i = 0; i < cuts.size(); ++i) {
    Point a{true, cuts[i], {}, {}, {}};
    if (hit(a)) return best;
    if (!earliest && i + 1 < cuts.size()) {
      Point mid{true, midpoint(cuts[i], cuts[i + 1]), {}, {}, {}};
      if (hit(mid)) return best;
    }
  }
  return best;
}

// The polynomials the predicates above may ask a sign of, in any branch, without repeats.
void add(std::vector<Poly>& out, const Poly& p) {
  if (p.degree() < 1) return;  // constants split nothing
  for (const Poly& q : out)
    if (q.c == p.c) return;
  out.push_back(p);
}
template <class P>
void add(std::vector<Poly>& out, const PV<P>& v) {
  for (const P& p : v) add(out, to_poly(p));
}
template <class P>
void on_segment_polys(const PV<P>& p, const PV<P>& a, const PV<P>& b, std::vector<Poly>& out) {
  const PV<P> ab = sub(b, a), ap = sub(p, a);
  add(out, ab);
  add(out, ap);
  add(out, cross(ab, ap));
  add(out, to_poly(dot(ap, ab)));
  add(out, to_poly(dot(sub(p, b), sub(a, b))));
}
// p on the segment [a, b] at some time (a vertex passing over an edge): where
// cross(b − a, p − a) vanishes, at the roots of the gcd of its components, or, when they all
// vanish identically (always collinear), wherever the betweenness signs allow.
template <class P>
double vertex_on_edge(const PV<P>& p, const PV<P>& a, const PV<P>& b, bool earliest) {
  const PV<P> c = cross(sub(b, a), sub(p, a));
  const Poly g = gcd(gcd(to_poly(c[0]), to_poly(c[1])), to_poly(c[2]));
  std::vector<Poly> polys;
  if (g.zero()) on_segment_polys(p, a, b, polys);
  return exists(
      g, polys, [&](Point& pt) { return on_segment(p, a, b, pt); }, earliest);
}

// Motion coplanar all step (the cubic of Dobritsa et al. eq. 13 vanishes identically). The times
// where the primitives meet form a closed set; at a time on its boundary other than 0 and 1 a
// vertex lies on an edge of the other primitive, because in a plane a proper crossing of two
// segments and a vertex strictly inside a triangle persist under small motions. So they meet at
// some time iff they meet at t = 0, at t = 1, or when a vertex passes over an edge, and the
// earliest time is among those. `passes` lists (vertex, edge end, edge end).
template <class P>
double coplanar_motion(const std::function<bool(Point&)>& meet,
                       const std::vector<std::array<const PV<P>*, 3>>& passes, bool earliest) {
  Point start{true, Q(0), {}, {}, {}};
  if (meet(start)) return 0.0;
  double best = -1.0;
  for (const auto& e : passes) {
    const double t = vertex_on_edge(*e[0], *e[1], *e[2], earliest);
    if (t >= 0.0 && (best < 0.0 || t < best)) best = t;
    if (best >= 0.0 && !earliest) return best;
  }
  if (best >= 0.0) return best;
  Point end{true, Q(1), {}, {}, {}};
  return meet(end) ? 1.0 : -1.0;
}

// Exact filter: the boxes of the two primitives over the step (their points at both ends) are
// disjoint. Points 0 … B − 1 (and 4 … 3 + B at the end) are the first primitive's, the rest the
// second's. The coordinates are doubles and comparisons of doubles are exact.
template <int B>
bool boxes_apart(const std::array<Vec3, 8>& q) {
  for (int d = 0; d < 3; ++d) {
    double lo0 = q[0][d], hi0 = lo0, lo1 = q[B][d], hi1 = lo1;
    for (int s = 0; s < 8; s += 4) {
      for (int k = s; k < s + B; ++k) lo0 = std::min(lo0, q[k][d]), hi0 = std::max(hi0, q[k][d]);
      for (int k = s + B; k < s + 4; ++k)
        lo1 = std::min(lo1, q[k][d]), hi1 = std::max(hi1, q[k][d]);
    }
    if (hi0 < lo1 || hi1 < lo0) return true;
  }
  return false;
}

// The certified Bernstein test (coplanarity.hpp): when all four S_k have one strict sign
// beyond their bounds, f has no root in [0, 1]: no contact. Undecided (false) when the sizes
// leave the normal range.
bool coplanarity_never_zero(const std::array<Vec3, 8>& q, int o, int i, int j, int k) {
  const Coplanarity c = coplanarity(q, o, i, j, k);
  if (!c.usable()) return false;
  const auto& [S, E] = c;
  const bool pos = S[0] > E[0] && S[1] > E[1] && S[2] > E[2] && S[3] > E[3];
  const bool neg = S[0] < -E[0] && S[1] < -E[1] && S[2] < -E[2] && S[3] < -E[3];
  return pos || neg;
}

// No motion (every point where it was: the verification's "touching at the start").
bool no_motion(const std::array<Vec3, 8>& q) {
  for (int k = 0; k < 4; ++k)
    if (q[k] != q[k + 4]) return false;
  return true;
}

// Without motion the determinant is one number, det[p_i − p_o, p_j − p_o, p_k − p_o] at t = 0,
// with the same error bound: a certain nonzero sign means the primitives are not coplanar and
// cannot meet.
bool certainly_not_coplanar(const std::array<Vec3, 8>& q, int o, int i, int j, int k) {
  const Vec3 x = q[i] - q[o];
  const BoundedCross cr = cross_bounded(q[j] - q[o], q[k] - q[o]);
  const double e = 16 * 0x1p-53 * cr.permanent(x);
  return usable_bound(e) && std::abs(cr.dot(x)) > e;
}

// The filters in front of the exact path: the exact box test (the first primitive has B of
// the four points), the certified Bernstein test of the coplanarity determinant
// det[p_i − p_o, p_j − p_o, p_k − p_o] and the interval subdivision. −1: no contact; 0:
// contact (when no time is asked: a time is always exact); NaN: undecided. A query without
// motion gets the determinant's one value and no subdivision (the exact static predicates are
// cheaper than subdividing a constant).
template <int B>
double filters(const std::array<Vec3, 8>& q, const std::array<int, 4>& det,
               Certain (*interval)(const std::array<Vec3, 8>&), bool earliest,
               const CcdFilters& use) {
  if (use.boxes && boxes_apart<B>(q)) return -1.0;
  if (no_motion(q)) {
    if (use.coplanarity && certainly_not_coplanar(q, det[0], det[1], det[2], det[3])) return -1.0;
    return std::nan("");
  }
  if (use.coplanarity && coplanarity_never_zero(q, det[0], det[1], det[2], det[3])) return -1.0;
  if (!use.interval) return std::nan("");
  const Certain sure = interval(q);
  if (sure == Certain::no) return -1.0;
  if (sure == Certain::yes && !earliest) return 0.0;
  return std::nan("");
}

// The four moving points of a query, on the integer scale of its coordinates.
template <class P>
std::array<PV<P>, 4> moving_points(const std::array<Vec3, 8>& q) {
  const long E = integer_exponent(q);
  return {moving<P>(q[0], q[4], E), moving<P>(q[1], q[5], E), moving<P>(q[2], q[6], E),
          moving<P>(q[3], q[7], E)};
}

// Without motion: the same predicates at the one time, on the integer coordinates directly,
// with no polynomial (I = Fixed or Z; sub and cross as above).
template <class I>
using IVec = std::array<I, 3>;
template <class I>
I integer_as(double x, long E) {
  if constexpr (std::is_same_v<I, Z>)
    return integer(x, E);
  else
    return fixed_integer<I::kWords>(x, E);
}
template <class I>
std::array<IVec<I>, 4> static_points(const std::array<Vec3, 8>& q) {
  const long E = integer_exponent(q);
  std::array<IVec<I>, 4> out;
  for (int k = 0; k < 4; ++k)
    for (int d = 0; d < 3; ++d) out[k][d] = integer_as<I>(q[k][d], E);
  return out;
}
template <class I>
int dot_sign(const IVec<I>& a, const IVec<I>& b) {
  const I r = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  return sgn(r);
}
template <class I>
bool is_zero(const IVec<I>& v) {
  return v[0] == 0 && v[1] == 0 && v[2] == 0;
}
// As on_segment, segments_meet and point_in_triangle above, at one time.
template <class I>
bool on_segment(const IVec<I>& p, const IVec<I>& a, const IVec<I>& b) {
  const IVec<I> ab = sub(b, a), ap = sub(p, a);
  if (is_zero(ab)) return is_zero(ap);
  if (!is_zero(cross(ab, ap))) return false;
  return dot_sign(ap, ab) >= 0 && dot_sign(sub(p, b), sub(a, b)) >= 0;
}
template <class I>
bool static_edges_meet(const std::array<Vec3, 8>& q) {
  const auto [a, b, c, d] = static_points<I>(q);
  const IVec<I> u = sub(b, a), v = sub(d, c);
  if (dot_sign(cross(u, sub(c, a)), sub(d, a)) != 0) return false;  // not coplanar
  const IVec<I> m = cross(u, v);
  if (!is_zero(m))
    return dot_sign(cross(u, sub(c, a)), m) * dot_sign(cross(u, sub(d, a)), m) <= 0 &&
           dot_sign(cross(v, sub(a, c)), m) * dot_sign(cross(v, sub(b, c)), m) <= 0;
  return on_segment(a, c, d) || on_segment(b, c, d) || on_segment(c, a, b) || on_segment(d, a, b);
}
template <class I>
bool static_vertex_in_face(const std::array<Vec3, 8>& q) {
  const auto [p, a, b, c] = static_points<I>(q);
  const IVec<I> n = cross(sub(b, a), sub(c, a));
  if (dot_sign(n, sub(p, a)) != 0) return false;  // not coplanar
  if (is_zero(n)) return on_segment(p, a, b) || on_segment(p, b, c) || on_segment(p, c, a);
  return dot_sign(cross(sub(b, a), sub(p, a)), n) >= 0 &&
         dot_sign(cross(sub(c, b), sub(p, b)), n) >= 0 &&
         dot_sign(cross(sub(a, c), sub(p, c)), n) >= 0;
}

// Fixed-width integers where the query's exponents allow (fixed_words) and the shortcuts are
// on, GMP's otherwise.
int words_for(const std::array<Vec3, 8>& q) {
  return shortcuts_on() ? fixed_words(q) : 0;
}
// f called with std::integral_constant<int, W>: the words of the query's Fixed, 0 for GMP.
template <class Fn>
auto by_width(const std::array<Vec3, 8>& q, Fn&& f) {
  switch (words_for(q)) {
    case 4:
      return f(std::integral_constant<int, 4>{});
    case 6:
      return f(std::integral_constant<int, 6>{});
    case 8:
      return f(std::integral_constant<int, 8>{});
    default:
      return f(std::integral_constant<int, 0>{});
  }
}
template <int W>
using IntegerOf = std::conditional_t<W == 0, Z, Fixed<W>>;
template <int W>
using PolyOf = std::conditional_t<W == 0, Poly, FPoly<W>>;
bool static_edges_meet(const std::array<Vec3, 8>& q) {
  return by_width(q, [&](auto w) { return static_edges_meet<IntegerOf<decltype(w)::value>>(q); });
}
bool static_vertex_in_face(const std::array<Vec3, 8>& q) {
  return by_width(q,
                  [&](auto w) { return static_vertex_in_face<IntegerOf<decltype(w)::value>>(q); });
}

// Touching at the start (resting contact) is a collision at t = 0, and touching at the end
// one at t = 1: the static predicates decide both at a fraction of the cost of the motion's
// roots (behind the determinant's certified sign, when the filters are on). With a time asked,
// only t = 0 answers at once (it is the earliest).
bool meet_at_an_end(const std::array<Vec3, 8>& q, bool (*meet)(const std::array<Vec3, 8>&),
                    const std::array<int, 4>& det, bool earliest, const CcdFilters& use) {
  const auto meet_at = [&](const std::array<Vec3, 8>& at) {
    if (use.coplanarity && certainly_not_coplanar(at, det[0], det[1], det[2], det[3])) return false;
    return meet(at);
  };
  std::array<Vec3, 8> at = q;
  for (int k = 0; k < 4; ++k) at[k + 4] = q[k];
  if (meet_at(at)) return true;
  if (earliest) return false;
  for (int k = 0; k < 4; ++k) at[k] = at[k + 4] = q[k + 4];
  return meet_at(at);
}

// The motion's roots and the inside test at them (after the filters and the ends).
template <class P>
double moving_vertex_face(const std::array<Vec3, 8>& q, bool earliest) {
  const auto [p, a, b, c] = moving_points<P>(q);
  const Poly coplanar = to_poly(dot(cross(sub(b, a), sub(c, a)), sub(p, a)));
  const auto meet = [&](Point& pt) { return point_in_triangle(p, a, b, c, pt); };
  if (coplanar.zero())
    return coplanar_motion<P>(meet, {{&p, &a, &b}, {&p, &b, &c}, {&p, &c, &a}}, earliest);
  return exists(coplanar, {}, meet, earliest);
}
template <class P>
double moving_edge_edge(const std::array<Vec3, 8>& q, bool earliest) {
  const auto [a, b, c, d] = moving_points<P>(q);
  const Poly coplanar = to_poly(dot(cross(sub(b, a), sub(c, a)), sub(d, a)));
  const auto meet = [&](Point& pt) { return segments_meet(a, b, c, d, pt); };
  if (coplanar.zero())
    return coplanar_motion<P>(meet, {{&a, &c, &d}, {&b, &c, &d}, {&c, &a, &b}, {&d, &a, &b}},
                              earliest);
  return exists(coplanar, {}, meet, earliest);
}

double vertex_face_query(const std::array<Vec3, 8>& q, bool earliest, const CcdFilters& use) {
  // det[b − a, c − a, p − a] for q = p, a, b, c.
  const std::array<int, 4> det{1, 2, 3, 0};
  const double f = filters<1>(q, det, interval_vertex_face_ccd, earliest, use);
  if (!std::isnan(f)) return f;
  if (no_motion(q)) return static_vertex_in_face(q) ? 0.0 : -1.0;
  if (meet_at_an_end(q, static_vertex_in_face, det, earliest, use)) return 0.0;
  return by_width(
      q, [&](auto w) { return moving_vertex_face<PolyOf<decltype(w)::value>>(q, earliest); });
}

double edge_edge_query(const std::array<Vec3, 8>& q, bool earliest, const CcdFilters& use) {
  // det[b − a, c − a, d − a] for q = a, b, c, d.
  const std::array<int, 4> det{0, 1, 2, 3};
  const double f = filters<2>(q, det, interval_edge_edge_ccd, earliest, use);
  if (!std::isnan(f)) return f;
  if (no_motion(q)) return static_edges_meet(q) ? 0.0 : -1.0;
  if (meet_at_an_end(q, static_edges_meet, det, earliest, use)) return 0.0;
  return by_width(
      q, [&](auto w) { return moving_edge_edge<PolyOf<decltype(w)::value>>(q, earliest); });
}

}  // namespace

void set_exact_ccd_shortcuts(bool on) {
  shortcuts.store(on);
}

bool exact_vertex_face_ccd(const std::array<Vec3, 8>& q, const CcdFilters& filters) {
  return vertex_face_query(q, false, filters) >= 0.0;
}
bool exact_edge_edge_ccd(const std::array<Vec3, 8>& q, const CcdFilters& filters) {
  return edge_edge_query(q, false, filters) >= 0.0;
}
namespace {
std::atomic<CcdObserver> observer{nullptr};
}  // namespace
void set_ccd_observer(CcdObserver o) {
  observer.store(o);
}
bool exact_vertex_face_ccd(const std::array<Vec3, 8>& q) {
  if (const CcdObserver o = observer.load(std::memory_order_relaxed)) o(false, q);
  return exact_vertex_face_ccd(q, CcdFilters{});
}
bool exact_edge_edge_ccd(const std::array<Vec3, 8>& q) {
  if (const CcdObserver o = observer.load(std::memory_order_relaxed)) o(true, q);
  return exact_edge_edge_ccd(q, CcdFilters{});
}
std::optional<double> exact_vertex_face_toi(const std::array<Vec3, 8>& q) {
  const double t = vertex_face_query(q, true, CcdFilters{});
  return t >= 0.0 ? std::optional<double>(t) : std::nullopt;
}
std::optional<double> exact_edge_edge_toi(const std::array<Vec3, 8>& q) {
  const double t = edge_edge_query(q, true, CcdFilters{});
  return t >= 0.0 ? std::optional<double>(t) : std::nullopt;
}

}  // namespace tc
