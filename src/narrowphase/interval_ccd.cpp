#include "tetcontact/narrowphase/interval_ccd.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "tetcontact/narrowphase/bounded_poly.hpp"

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

// Separating axes, in doubles with certified error bounds: over a time span T = [t0, t1] each
// point x(t) = x0 + t (x1 − x0) projects on a fixed direction s linearly in t, so over T its
// projection lies between its projections at t0 and t1, and a segment's or a triangle's
// between its vertices'. The primitives cannot meet in T when the hulls of their points'
// projections at both ends are disjoint. Used over the whole step first (most pairs of a
// contact interface, sliding past each other), then as the inside test's fallback on a span,
// where its orientations are too close to 0 to sign (parallel or nearly parallel coplanar
// edges). Errors: x(t) computed in doubles errs by at most 3 ε (|x0| + t |x1 − x0|) per
// coordinate (the difference, the product, the sum; ε = 2⁻⁵³), and x·s by 3 ε Σ|x_d s_d| more;
// each projection is widened by 4 ε of both and by 2⁻¹⁰⁰⁰ against underflow. Any direction
// will do for soundness; they are chosen at T's middle: the primitives' directions, and the
// directions across each edge towards the other primitive.
bool separated_over(const std::array<Vec3, 8>& q, int first_b, double t0, double t1) {
  constexpr double k4eps = 0x1p-51;
  // The points at both ends of T, with a bound on each coordinate's rounding error.
  std::array<Vec3, 8> x, err;
  std::array<Vec3, 4> mid;
  const double tm = 0.5 * (t0 + t1);
  for (int n = 0; n < 4; ++n) {
    const Vec3 d = q[4 + n] - q[n];
    for (int end = 0; end < 2; ++end) {
      const double t = end == 0 ? t0 : t1;
      x[4 * end + n] = q[n] + t * d;
      err[4 * end + n] = k4eps * (q[n].cwiseAbs() + t * d.cwiseAbs());
    }
    mid[n] = q[n] + tm * d;
  }
  const auto apart = [&](const Vec3& s) {
    if (!(s.squaredNorm() > 0.0) || !s.allFinite()) return false;
    const Vec3 as = s.cwiseAbs();
    double lo[2] = {1e308, 1e308}, hi[2] = {-1e308, -1e308};
    for (int k = 0; k < 8; ++k) {
      const Vec3& p = x[k];
      const double v = p[0] * s[0] + p[1] * s[1] + p[2] * s[2];
      const double e =
          k4eps * (std::abs(p[0] * s[0]) + std::abs(p[1] * s[1]) + std::abs(p[2] * s[2])) +
          (1 + k4eps) * (err[k][0] * as[0] + err[k][1] * as[1] + err[k][2] * as[2]) + 0x1p-1000;
      if (!std::isfinite(v - e) || !std::isfinite(v + e)) return false;  // overflow: undecided
      const int side = (k & 3) < first_b ? 0 : 1;
      lo[side] = std::min(lo[side], v - e);
      hi[side] = std::max(hi[side], v + e);
    }
    return hi[0] < lo[1] || hi[1] < lo[0];
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
  Points p;
  for (int n = 0; n < 4; ++n) {
    BoundedPoly* coord[3] = {&p[n].x, &p[n].y, &p[n].z};
    for (int d = 0; d < 3; ++d) {
      const double x0 = q[n][d], x1 = q[4 + n][d];
      if (!(std::abs(x0) < kLimit && std::abs(x1) < kLimit)) return Certain::unknown;
      *coord[d] = BoundedPoly::moving(x0, x1);
    }
  }
  const IPoly f = enclosure(dot(p[i] - p[o], cross(p[j] - p[o], p[k] - p[o])));
  Inside inside;
  const auto inside_over = [&](double t0, double t1) {
    if (inside.count == 0) inside = make_inside(p);
    const auto value = [&](int n) {
      return t0 == t1 ? at(inside.polys[n], t0) : over(inside.polys[n], t0, t1);
    };
    const Certain c = inside.edges ? edges_rule(value) : face_rule(value);
    if (c == Certain::unknown && separated_over(q, first_b, t0, t1)) return Certain::no;
    return c;
  };
  // Coplanar and possibly meeting at t = 0 or 1 (touching at the start, as resting contact
  // gives): no span ending there can ever be certified, so the exact path answers at once.
  for (const double t : {0.0, 1.0}) {
    const Iv ft = at(f, t);
    if (!positive(ft) && !negative(ft) && inside_over(t, t) != Certain::no) return Certain::unknown;
  }
  struct Span {
    double t0, t1;
    int depth;
  };
  Span stack[2 * kMaxDepth + 2];
  int top = 0, spans = 0;
  stack[top++] = {0.0, 1.0, 0};
  while (top > 0) {
    const Span s = stack[--top];
    if (++spans > kMaxSpans) return Certain::unknown;
    const Iv fs = over(f, s.t0, s.t1);
    if (positive(fs) || negative(fs)) continue;  // never coplanar in T
    const Certain in = inside_over(s.t0, s.t1);
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
