#include "tetcontact/narrowphase/interval_ccd.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <utility>

#include "tetcontact/narrowphase/bounded_poly.hpp"
#include "tetcontact/narrowphase/coplanarity.hpp"

namespace tc {
namespace {

// An interval of reals. Every operation rounds to nearest and then widens each end by
// 2⁻⁵¹|x| + 2⁻¹⁰²²: rounding to nearest errs by at most half an ulp, which is at most 2⁻⁵³|x|
// for a normal result and 2⁻¹⁰⁷⁵ below, so the exact result stays inside (the widening's own
// rounding is smaller than the margin). An overflow gives infinite or NaN ends, for which
// every strict test below is false: undecided, never wrong. Coordinates are limited to
// 2¹⁰⁰ in size, so that the degree-4 products below cannot overflow.
struct Iv {
  double lo, hi;
};
constexpr double kRel = 0x1p-51, kAbs = 0x1p-1022;
double down(double x) {
  return x - (std::abs(x) * kRel + kAbs);
}
double up(double x) {
  return x + (std::abs(x) * kRel + kAbs);
}
Iv operator+(Iv a, Iv b) {
  return {down(a.lo + b.lo), up(a.hi + b.hi)};
}
// The double t times an interval (two products instead of four).
Iv scaled(double t, Iv a) {
  const double p = t * a.lo, q = t * a.hi;
  return {down(std::min(p, q)), up(std::max(p, q))};
}
bool positive(Iv a) {
  return a.lo > 0.0;
}
bool negative(Iv a) {
  return a.hi < 0.0;
}
bool opposite(Iv a, Iv b) {
  return (positive(a) && negative(b)) || (negative(a) && positive(b));
}
bool same(Iv a, Iv b) {
  return (positive(a) && positive(b)) || (negative(a) && negative(b));
}

double magnitude(Iv a) {
  return std::max(std::abs(a.lo), std::abs(a.hi));
}

// A polynomial in t of degree ≤ 4 with interval coefficients, c[k] for t^k.
struct IPoly {
  std::array<Iv, 5> c{};
  int n = 0;  // number of coefficients
};
// Value at the double t (an interval holding the exact value).
Iv at(const IPoly& p, double t) {
  Iv r{0.0, 0.0};
  for (int k = p.n; k-- > 0;) r = scaled(t, r) + p.c[k];
  return r;
}
// An interval holding p(t) for every t in [t0, t1]: the centred form about m = (t0 + t1)/2,
//   p(m + s) = Σ g_k s^k,  |s| ≤ r  ⇒  p ∈ g_0 ± Σ_{k≥1} |g_k| r^k,
// with the Taylor coefficients g_k at m from repeated Horner steps. Its width shrinks like
// r², so spans about a simple root are resolved in a few halvings.
Iv over(const IPoly& p, double t0, double t1) {
  const double m = 0.5 * (t0 + t1);
  const double r = up(std::max(t1 - m, m - t0));
  std::array<Iv, 5> g = p.c;
  // g_k + m g_(k+1) with m ≥ 0, each end rounded twice (the product, the sum) and widened
  // once by the bound of both, 2⁻⁵¹ (|m g| + |sum|) + 2⁻¹⁰²².
  const auto step = [m](double a, double b, double side) {
    const double prod = m * b, sum = a + prod;
    return sum + side * ((std::abs(prod) + std::abs(sum)) * kRel + kAbs);
  };
  for (int i = 0; i + 1 < p.n; ++i)
    for (int k = p.n - 2; k >= i; --k)
      g[k] = {step(g[k].lo, g[k + 1].lo, -1.0), step(g[k].hi, g[k + 1].hi, 1.0)};
  double spread = 0.0, rk = 1.0;
  for (int k = 1; k < p.n; ++k) {
    rk = up(rk * r);
    spread = up(spread + up(magnitude(g[k]) * rk));
  }
  return p.n == 0 ? Iv{0.0, 0.0} : Iv{down(g[0].lo - spread), up(g[0].hi + spread)};
}

// The derivative's enclosure: k c_k for each k ≥ 1 (scaled rounds outward).
IPoly derivative(const IPoly& p) {
  IPoly d;
  d.n = std::max(p.n - 1, 0);
  for (int k = 1; k < p.n; ++k) d.c[k - 1] = scaled(k, p.c[k]);
  return d;
}

// The enclosure of a polynomial formed in doubles with its error bounds (bounded_poly.hpp):
// each coefficient v ± (e (1 + 2⁻⁴⁵) + 2⁻¹⁰⁰⁰), the bound widened for its own rounding (and by a
// margin), and the ends once more for theirs. A non-finite value or bound gives non-finite
// ends, which no strict test below passes: undecided.
IPoly enclosure(const BoundedPoly& p) {
  IPoly r;
  r.n = p.n;
  for (int k = 0; k < p.n; ++k) {
    const double e = up(p.e[k] * (1.0 + 0x1p-45) + 0x1p-1000);
    r.c[k] = {down(p.v[k] - e), up(p.v[k] + e)};
  }
  return r;
}

// A point's positions over a time span [t0, t1] ⊂ [0, 1] as one value with its bound
// (bounded_poly.hpp): x0 + m d at the span's middle m, d = x1 − x0 rounded, off from the exact
// x(t) = x0 + t (x1 − x0) by at most 2 ε m |d| + ε |value| (the roundings) + r |d| (1 + 2 ε)
// (the span, r ≥ |t − m|) + 2⁻¹⁰²² (an underflow of m d). On a narrow span (a bracketed
// root) the inside test's orientations computed from these enclose their values over the
// span about as tightly as the polynomials do, without forming them.
Bounded3 point_over(const Vec3& x0, const Vec3& x1, double m, double r) {
  constexpr double eps = BoundedPoly::kEps;
  Bounded3 p;
  for (int d = 0; d < 3; ++d) {
    const double step = x1[d] - x0[d], v = x0[d] + m * step, size = std::abs(step);
    p.x[d] = {v, 2 * eps * m * size + eps * std::abs(v) + r * size * (1 + 2 * eps) + 0x1p-1022};
  }
  return p;
}
// A value with its bound as an interval, the bound widened for its own rounding as in
// enclosure() below.
Iv interval(Bounded b) {
  const double e = up(b.e * (1.0 + 0x1p-45) + 0x1p-1000);
  return {down(b.v - e), up(b.v + e)};
}

// The coplanarity determinant from its Bernstein sums S_k ± E_k (coplanarity.hpp) in powers
// of t, (1 − t)³ = 1 − 3t + 3t² − t³, (1 − t)² t = t − 2t² + t³, (1 − t) t² = t² − t³:
//   c₀ = S₀,  c₁ = S₁ − 3S₀,  c₂ = S₂ − 2S₁ + 3S₀,  c₃ = S₃ − S₂ + S₁ − S₀,
// each c_k = Σ_j a_kj S_j off by Σ_j |a_kj| E_j from the S_j's errors and by at most 3 roundings
// of partial sums, 4 ε Σ_j |a_kj S_j| (a product below the normal range, 3 S₀, is covered by
// the enclosure's absolute margin).
BoundedPoly power_basis(const Coplanarity& c) {
  constexpr double a[4][4] = {{1, 0, 0, 0}, {-3, 1, 0, 0}, {3, -2, 1, 0}, {-1, 1, -1, 1}};
  const auto& [S, E] = c;
  BoundedPoly p;
  p.n = 4;
  p.v = {S[0], S[1] - 3 * S[0], (S[2] - 2 * S[1]) + 3 * S[0], ((S[3] - S[2]) + S[1]) - S[0], 0.0};
  for (int k = 0; k < 4; ++k) {
    double from_s = 0.0, size = 0.0;
    for (int j = 0; j <= k; ++j) {
      from_s += std::abs(a[k][j]) * E[j];
      size += std::abs(a[k][j] * S[j]);
    }
    p.e[k] = from_s + 4 * BoundedPoly::kEps * size;
  }
  return p;
}

using Points = std::array<BoundedVec, 4>;
// The polynomials whose signs decide the inside test at a coplanar time, and which rule.
struct Inside {
  std::array<IPoly, 4> polys;
  int count = 0;
  bool edges = false;  // edges_rule, else face_rule
};

// Edges [a, b] and [c, d], coplanar at the times asked about. With m = (b − a) × (d − c) ≠ 0
// they meet iff c, d are not strictly on one side of line ab, nor a, b of line cd (the
// orientations o = ((b − a) × (c − a))·m and so on): `no` when one pair is strictly on one
// side over all of T, `yes` when both pairs are strictly on opposite sides over all of T.
// `o(n)` encloses the n-th orientation over T; each is formed only when the rule needs it.
template <class Value>
Certain edges_rule(const Value& o) {
  const Iv o0 = o(0), o1 = o(1);
  if (same(o0, o1)) return Certain::no;
  const Iv o2 = o(2), o3 = o(3);
  if (same(o2, o3)) return Certain::no;
  return opposite(o0, o1) && opposite(o2, o3) ? Certain::yes : Certain::unknown;
}
Inside edges_meet(const Points& p) {
  const BoundedVec u = p[1] - p[0], v = p[3] - p[2], m = cross(u, v);
  return {{enclosure(dot(cross(u, p[2] - p[0]), m)), enclosure(dot(cross(u, p[3] - p[0]), m)),
           enclosure(dot(cross(v, p[0] - p[2]), m)), enclosure(dot(cross(v, p[1] - p[2]), m))},
          4,
          true};
}

// Vertex p[0] and triangle p[1..3], coplanar at the times asked about: inside iff on the inner
// side of each edge, measured along the triangle's normal n.
template <class Value>
Certain face_rule(const Value& side) {
  bool all_positive = true;
  for (int n = 0; n < 3; ++n) {
    const Iv s = side(n);
    if (negative(s)) return Certain::no;
    all_positive = all_positive && positive(s);
  }
  return all_positive ? Certain::yes : Certain::unknown;
}
Inside vertex_in_face(const Points& p) {
  const BoundedVec &v = p[0], &a = p[1], &b = p[2], &c = p[3];
  const BoundedVec n = cross(b - a, c - a);
  return {{enclosure(dot(cross(b - a, v - a), n)), enclosure(dot(cross(c - b, v - b), n)),
           enclosure(dot(cross(a - c, v - c), n)), IPoly{}},
          3,
          false};
}

// The inside test over [t0, t1] on the points' boxes (edges when first_b is 2, else a vertex
// and a face), the same rules as above.
Certain inside_on_boxes(const std::array<Vec3, 8>& q, int first_b, double t0, double t1) {
  const double m = 0.5 * (t0 + t1), r = up(std::max(t1 - m, m - t0));
  std::array<Bounded3, 4> x;
  for (int n = 0; n < 4; ++n) x[n] = point_over(q[n], q[4 + n], m, r);
  if (first_b == 2) {
    const Bounded3 u = x[1] - x[0], v = x[3] - x[2], w = cross(u, v);
    return edges_rule([&](int n) {
      return interval(n < 2 ? dot(cross(u, x[2 + n] - x[0]), w)
                            : dot(cross(v, x[n - 2] - x[2]), w));
    });
  }
  const Bounded3 n = cross(x[2] - x[1], x[3] - x[1]);
  return face_rule([&](int k) {
    const Bounded3 &a = x[1 + k], &b = x[1 + (k + 1) % 3];
    return interval(dot(cross(b - a, x[0] - a), n));
  });
}

// Separating axes, in doubles with certified error bounds: over a time span T = [t0, t1] each
// point x(t) = x0 + t (x1 − x0) projects on a fixed direction s linearly in t, so over T its
// projection lies between its projections at t0 and t1, and a segment's or a triangle's
// between its vertices'. The primitives cannot meet in T when the hulls of their points'
// projections at both ends are disjoint. Used over the whole step first (most pairs of a
// contact interface, sliding past each other), then as the inside test's fallback on a span,
// where its orientations are too close to 0 to sign (parallel or nearly parallel coplanar
// edges). Errors, with A_d the largest |coordinate d| of the query's eight points (t ∈ [0, 1],
// ε = 2⁻⁵³): x(t) computed in doubles errs by at most 3 ε (|x0| + t |x1 − x0|) ≤ 9 ε A_d per
// coordinate (the difference, the product, the sum), and x·s by 3 ε Σ |x_d s_d| ≤ 3 ε (1 + 9 ε)
// Σ A_d |s_d| more; every projection is widened by 32 ε Σ A_d |s_d| (the margin covers that
// sum's own rounding) and by 2⁻¹⁰⁰⁰ against underflow. Any direction will do for soundness;
// they are chosen at T's middle: the primitives' directions, and the directions across each
// edge towards the other primitive.
bool separated_over(const std::array<Vec3, 8>& q, int first_b, double t0, double t1) {
  std::array<Vec3, 8> x;
  std::array<Vec3, 4> mid;
  Vec3 size = Vec3::Zero();
  const double tm = 0.5 * (t0 + t1);
  for (int n = 0; n < 4; ++n) {
    const Vec3 d = q[4 + n] - q[n];
    x[n] = q[n] + t0 * d;
    x[4 + n] = q[n] + t1 * d;
    mid[n] = q[n] + tm * d;
    size = size.cwiseMax(q[n].cwiseAbs()).cwiseMax(q[4 + n].cwiseAbs());
  }
  // Coordinates below 2¹⁰⁰ (NaN fails too): the directions, of degree ≤ 3 in them, and the
  // projections stay far from overflow.
  if (!(size.maxCoeff() < 0x1p100)) return false;
  const auto apart = [&](const Vec3& s) {
    if (!(s.squaredNorm() > 0.0) || !s.allFinite()) return false;
    const double e = 0x1p-48 * size.dot(s.cwiseAbs()) + 0x1p-1000;
    double lo[2] = {1e308, 1e308}, hi[2] = {-1e308, -1e308};
    for (int k = 0; k < 8; ++k) {
      const double v = x[k].dot(s);
      const int side = (k & 3) < first_b ? 0 : 1;
      lo[side] = std::min(lo[side], v);
      hi[side] = std::max(hi[side], v);
    }
    return hi[0] + e < lo[1] - e || hi[1] + e < lo[0] - e;
  };
  // Across the edge e (from `from`), towards the point `to`: the part of to − from normal to e.
  const auto across = [&](const Vec3& from, const Vec3& e, const Vec3& to) {
    const Vec3 w = to - from;
    return Vec3(w * e.squaredNorm() - e * e.dot(w));
  };
  if (first_b == 2) {  // edges [a, b] and [c, d]
    const Vec3 u = mid[1] - mid[0], v = mid[3] - mid[2];
    return apart(u) || apart(v) || apart(across(mid[0], u, 0.5 * (mid[2] + mid[3]))) ||
           apart(across(mid[2], v, 0.5 * (mid[0] + mid[1])));
  }
  // Vertex p and triangle (a, b, c): across each edge, away from the opposite vertex.
  for (int k = 0; k < 3; ++k) {
    const Vec3 &a = mid[1 + k], &b = mid[1 + (k + 1) % 3], &c = mid[1 + (k + 2) % 3];
    if (apart(across(a, b - a, c))) return true;
  }
  return false;
}

// The one root of f in (t0, t1), where f is monotone and f0, f1 are its certified values at
// t0 and t1, of opposite strict signs: a span [a, b] whose ends' values are certified to have
// f0's and f1's signs, so that the root lies inside and f ≠ 0 on the rest. First a guess,
// Newton's steps in doubles on the coefficients' middles from the secant's time, kept when the
// signs 2⁻³¹ either side of it are certified; else false position (Illinois) on certified
// values down to a width of 2⁻³⁰, stopping early where a value's sign is uncertain (the time
// is then within the value's error of the root).
struct Bracket {
  double a, b;
  bool tight;  // as narrow as the width asked for, or as f's certified signs allow
};
Bracket bracket_root(const IPoly& f, double t0, double t1, Iv f0, Iv f1) {
  constexpr double kWidth = 0x1p-45;
  constexpr int kMaxSteps = 40;
  const auto middle = [](Iv v) { return 0.5 * (v.lo + v.hi); };
  double a = t0, b = t1, fa = middle(f0), fb = middle(f1);
  double t = (a * fb - b * fa) / (fb - fa);
  for (int it = 0; it < 4 && t > a && t < b; ++it) {
    double v = 0.0, dv = 0.0;
    for (int n = f.n; n-- > 0;) dv = dv * t + v, v = v * t + middle(f.c[n]);
    t -= v / dv;
  }
  for (double w = kWidth; w < 0x1p-20 && t - w > a && t + w < b; w *= 0x1p8) {
    const Iv lo = at(f, t - w), hi = at(f, t + w);
    if (same(lo, f0) && same(hi, f1)) return {t - w, t + w, true};
    if (!(same(lo, f0) || same(lo, f1)) || !(same(hi, f0) || same(hi, f1))) continue;
    break;  // a sign on the wrong side: the guess is off, not uncertain
  }
  int kept = 0;  // Illinois: halve the value at the end kept twice running
  for (int it = 0; it < kMaxSteps && b - a > kWidth; ++it) {
    t = (a * fb - b * fa) / (fb - fa);
    if (!(t > a && t < b)) t = 0.5 * (a + b);
    const Iv ft = at(f, t);
    // The signs come from the certified values; fa and fb only steer the next guess.
    if (same(ft, f0)) {
      a = t, fa = middle(ft);
      if (kept == 1) fb *= 0.5;
      kept = 1;
    } else if (same(ft, f1)) {
      b = t, fb = middle(ft);
      if (kept == -1) fa *= 0.5;
      kept = -1;
    } else {
      break;
    }
  }
  return {a, b, b - a <= kWidth};
}

// Subdivision of [0, 1] as described in the header. `o, i, j, k` pick the points of the
// coplanarity determinant det[p_i − p_o, p_j − p_o, p_k − p_o]; `make_inside` builds the inside
// test's polynomials (only when a span may hold a root).
Certain subdivide(const std::array<Vec3, 8>& q, int o, int i, int j, int k,
                  Inside (*make_inside)(const Points&), int first_b) {
  constexpr double kLimit = 0x1p100;
  constexpr int kMaxDepth = 30, kMaxSpans = 48;
  // Apart along a direction over the whole step (most pairs of a contact interface: sliding
  // past each other, often coplanar at some time): no polynomial needed.
  if (separated_over(q, first_b, 0.0, 1.0)) return Certain::no;
  for (const Vec3& x : q)
    if (!(x.cwiseAbs().maxCoeff() < kLimit)) return Certain::unknown;
  // The points as polynomials in t, formed when first needed.
  std::optional<Points> p;
  const auto points = [&]() -> const Points& {
    if (!p) {
      p.emplace();
      for (int n = 0; n < 4; ++n)
        (*p)[n] = {BoundedPoly::moving(q[n][0], q[4 + n][0]),
                   BoundedPoly::moving(q[n][1], q[4 + n][1]),
                   BoundedPoly::moving(q[n][2], q[4 + n][2])};
    }
    return *p;
  };
  // The determinant from the Bernstein sums, or from the polynomials where their bounds leave
  // the normal range.
  const Coplanarity bern = coplanarity(q, o, i, j, k);
  const IPoly f = bern.usable() ? enclosure(power_basis(bern)) : [&] {
    const Points& x = points();
    return enclosure(dot(x[i] - x[o], cross(x[j] - x[o], x[k] - x[o])));
  }();
  Inside inside;
  // The inside test over [t0, t1]: on the points' boxes where the span is a point or a
  // bracketed root, else on the polynomials' centred forms (formed at the first such call).
  const auto inside_over = [&](double t0, double t1, bool boxes) {
    Certain c;
    if (boxes) {
      c = inside_on_boxes(q, first_b, t0, t1);
    } else {
      if (inside.count == 0) inside = make_inside(points());
      const auto value = [&](int n) { return over(inside.polys[n], t0, t1); };
      c = inside.edges ? edges_rule(value) : face_rule(value);
    }
    if (c == Certain::unknown && separated_over(q, first_b, t0, t1)) return Certain::no;
    return c;
  };
  // Coplanar and possibly meeting at t = 0 or 1 (touching at the start, as resting contact
  // gives): no span ending there can ever be certified, so the exact path answers at once.
  for (const double t : {0.0, 1.0}) {
    const Iv ft = at(f, t);
    if (!positive(ft) && !negative(ft) && inside_over(t, t, true) != Certain::no)
      return Certain::unknown;
  }
  struct Span {
    double t0, t1;
    int depth;
  };
  Span stack[2 * kMaxDepth + 2];
  int top = 0, spans = 0;
  stack[top++] = {0.0, 1.0, 0};
  const IPoly df = derivative(f);
  while (top > 0) {
    Span s = stack[--top];
    if (++spans > kMaxSpans) return Certain::unknown;
    const Iv fs = over(f, s.t0, s.t1);
    if (positive(fs) || negative(fs)) continue;  // never coplanar in T
    // Monotone on T (f' of one strict sign) with strict signs at T's ends: no root when they
    // agree, else exactly one, bracketed in [a, b]; f ≠ 0 on the rest of T, so only [a, b] is
    // asked about, first on the points' boxes, then (undecided) as a span of its own.
    const Iv f0 = at(f, s.t0), f1 = at(f, s.t1), dfs = over(df, s.t0, s.t1);
    if ((positive(f0) || negative(f0)) && (positive(f1) || negative(f1)) &&
        (positive(dfs) || negative(dfs))) {
      if (same(f0, f1)) continue;
      const auto [a, b, tight] = bracket_root(f, s.t0, s.t1, f0, f1);
      Certain in = inside_over(a, b, true);
      // Undecided on a root's narrow bracket: once more on the polynomials (no box's
      // overestimate), then touching or nearly so at the root, which no narrower span decides.
      if (in == Certain::unknown && tight) in = inside_over(a, b, false);
      if (in == Certain::no) continue;
      if (in == Certain::yes) return Certain::yes;  // f changes sign strictly inside [a, b]
      if (tight) return Certain::unknown;
      s = {a, b, s.depth};
    }
    const Certain in = inside_over(s.t0, s.t1, false);
    if (in == Certain::no) continue;  // coplanar or not, never meeting in T
    if (in == Certain::yes && opposite(at(f, s.t0), at(f, s.t1)))
      return Certain::yes;  // a coplanar time in T, where they meet
    if (s.depth == kMaxDepth) return Certain::unknown;
    // Split off-centre: roots of structured input sit at 1/2, 1/4, … where a certified sign
    // is impossible; the split points t0 + 15/32 (t1 − t0) avoid them.
    const double mid = s.t0 + 0.46875 * (s.t1 - s.t0);
    stack[top++] = {mid, s.t1, s.depth + 1};
    stack[top++] = {s.t0, mid, s.depth + 1};
  }
  return Certain::no;
}

}  // namespace

Certain interval_vertex_face_ccd(const std::array<Vec3, 8>& q) {
  return subdivide(q, 1, 2, 3, 0, vertex_in_face, 1);  // det[b − a, c − a, p − a]
}

Certain interval_edge_edge_ccd(const std::array<Vec3, 8>& q) {
  return subdivide(q, 0, 1, 2, 3, edges_meet, 2);  // det[b − a, c − a, d − a]
}

}  // namespace tc
