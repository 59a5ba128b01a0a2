#include "tetcontact/narrowphase/interval_ccd.hpp"

#include <algorithm>
#include <cmath>

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
Iv operator-(Iv a, Iv b) {
  return {down(a.lo - b.hi), up(a.hi - b.lo)};
}
Iv operator*(Iv a, Iv b) {
  const double p = a.lo * b.lo, q = a.lo * b.hi, r = a.hi * b.lo, s = a.hi * b.hi;
  return {down(std::min(std::min(p, q), std::min(r, s))),
          up(std::max(std::max(p, q), std::max(r, s)))};
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

struct IVec {
  Iv x, y, z;
};
IVec operator-(const IVec& a, const IVec& b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
IVec cross(const IVec& a, const IVec& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
Iv dot(const IVec& a, const IVec& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}

using Points = std::array<IVec, 4>;

// Edges [a, b] and [c, d], coplanar at the times asked about. With m = (b − a) × (d − c) ≠ 0
// they meet iff c, d are not strictly on one side of line ab, nor a, b of line cd (the
// orientations o = ((b − a) × (c − a))·m and so on): `no` when one pair is strictly on one
// side over all of T, `yes` when both pairs are strictly on opposite sides over all of T.
Certain edges_meet(const Points& p) {
  const IVec u = p[1] - p[0], v = p[3] - p[2], m = cross(u, v);
  const Iv o1 = dot(cross(u, p[2] - p[0]), m), o2 = dot(cross(u, p[3] - p[0]), m);
  const Iv o3 = dot(cross(v, p[0] - p[2]), m), o4 = dot(cross(v, p[1] - p[2]), m);
  if (same(o1, o2) || same(o3, o4)) return Certain::no;
  return opposite(o1, o2) && opposite(o3, o4) ? Certain::yes : Certain::unknown;
}

// Vertex p[0] and triangle p[1..3], coplanar at the times asked about: inside iff on the inner
// side of each edge, measured along the triangle's normal n.
Certain vertex_in_face(const Points& p) {
  const IVec &v = p[0], &a = p[1], &b = p[2], &c = p[3];
  const IVec n = cross(b - a, c - a);
  const Iv s1 = dot(cross(b - a, v - a), n), s2 = dot(cross(c - b, v - b), n),
           s3 = dot(cross(a - c, v - c), n);
  if (negative(s1) || negative(s2) || negative(s3)) return Certain::no;
  return positive(s1) && positive(s2) && positive(s3) ? Certain::yes : Certain::unknown;
}

// Subdivision of [0, 1] as described in the header. `o, i, j, k` pick the points of the
// coplanarity determinant det[p_i − p_o, p_j − p_o, p_k − p_o].
template <class Inside>
Certain bisect_step(const std::array<Vec3, 8>& q, int o, int i, int j, int k, Inside inside) {
  constexpr double kLimit = 0x1p100;
  constexpr int kMaxDepth = 30, kMaxSpans = 160;
  Points start, motion;
  for (int n = 0; n < 4; ++n) {
    IVec s, m;
    Iv* sc[3] = {&s.x, &s.y, &s.z};
    Iv* mc[3] = {&m.x, &m.y, &m.z};
    for (int d = 0; d < 3; ++d) {
      const double x0 = q[n][d], x1 = q[4 + n][d];
      if (!(std::abs(x0) < kLimit && std::abs(x1) < kLimit)) return Certain::unknown;
      *sc[d] = {x0, x0};
      *mc[d] = Iv{x1, x1} - Iv{x0, x0};
    }
    start[n] = s;
    motion[n] = m;
  }
  const auto at = [&](Iv t) {
    Points p;
    for (int n = 0; n < 4; ++n)
      p[n] = {start[n].x + t * motion[n].x, start[n].y + t * motion[n].y,
              start[n].z + t * motion[n].z};
    return p;
  };
  const auto coplanarity = [&](const Points& p) {
    return dot(p[i] - p[o], cross(p[j] - p[o], p[k] - p[o]));
  };
  // Coplanar and possibly meeting at t = 0 or 1 (touching at the start, as resting contact
  // gives): no span ending there can ever be certified, so the exact path answers at once.
  for (const double t : {0.0, 1.0}) {
    const Points p = at({t, t});
    const Iv f = coplanarity(p);
    if (!positive(f) && !negative(f) && inside(p) != Certain::no) return Certain::unknown;
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
    const Points p = at({s.t0, s.t1});
    const Iv f = coplanarity(p);
    if (positive(f) || negative(f)) continue;  // never coplanar in T
    const Certain in = inside(p);
    if (in == Certain::no) continue;  // coplanar or not, never meeting in T
    if (in == Certain::yes &&
        opposite(coplanarity(at({s.t0, s.t0})), coplanarity(at({s.t1, s.t1}))))
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
  return bisect_step(q, 1, 2, 3, 0, vertex_in_face);  // det[b − a, c − a, p − a]
}

Certain interval_edge_edge_ccd(const std::array<Vec3, 8>& q) {
  return bisect_step(q, 0, 1, 2, 3, edges_meet);  // det[b − a, c − a, d − a]
}

}  // namespace tc
