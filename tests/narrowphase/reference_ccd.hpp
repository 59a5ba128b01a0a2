// A slow exact CCD reference for the tests, written apart from src/narrowphase/exact_ccd.cpp
// and sharing no code with it: rational arithmetic (GMP's mpq_class), Sturm sequences by plain
// polynomial division over Q, roots isolated by bisection at rational points. It decides only
// the non-degenerate queries: the coplanarity cubic (Dobritsa et al. eq. 13) not identically zero
// and not zero at t = 0 or 1, every root in (0, 1) isolated, and at each root the inside test
// strictly decided (no touching, no parallel edges, no degenerate face). For the rest it says
// "undecided": tests compare only where it decides.
#pragma once

#include <gmpxx.h>

#include <array>
#include <optional>
#include <vector>

#include "tetcontact/mesh/mesh.hpp"

namespace tc::reference {

using Poly = std::vector<mpq_class>;  // coefficients, lowest degree first

inline void trim(Poly& p) {
  while (!p.empty() && p.back() == 0) p.pop_back();
}
inline Poly add(const Poly& a, const Poly& b, int sign = 1) {
  Poly r(std::max(a.size(), b.size()));
  for (std::size_t i = 0; i < a.size(); ++i) r[i] += a[i];
  for (std::size_t i = 0; i < b.size(); ++i) r[i] += sign * b[i];
  trim(r);
  return r;
}
inline Poly mul(const Poly& a, const Poly& b) {
  if (a.empty() || b.empty()) return {};
  Poly r(a.size() + b.size() - 1);
  for (std::size_t i = 0; i < a.size(); ++i)
    for (std::size_t j = 0; j < b.size(); ++j) r[i + j] += a[i] * b[j];
  trim(r);
  return r;
}
inline mpq_class eval(const Poly& p, const mpq_class& t) {
  mpq_class v = 0;
  for (std::size_t i = p.size(); i-- > 0;) v = v * t + p[i];
  return v;
}
inline int sign(const mpq_class& q) {
  return sgn(q);
}
// Remainder of a divided by b (b non-zero).
inline Poly rem(Poly a, const Poly& b) {
  while (a.size() >= b.size() && !a.empty()) {
    const mpq_class f = a.back() / b.back();
    const std::size_t shift = a.size() - b.size();
    for (std::size_t i = 0; i < b.size(); ++i) a[i + shift] -= f * b[i];
    trim(a);
  }
  return a;
}
inline std::vector<Poly> sturm(const Poly& p) {
  std::vector<Poly> s{p};
  Poly d;
  for (std::size_t i = 1; i < p.size(); ++i) d.push_back(p[i] * static_cast<long>(i));
  trim(d);
  if (d.empty()) return s;
  s.push_back(d);
  while (true) {
    Poly r = rem(s[s.size() - 2], s.back());
    if (r.empty()) break;
    for (mpq_class& c : r) c = -c;
    s.push_back(r);
  }
  return s;
}
inline int changes(const std::vector<Poly>& s, const mpq_class& x) {
  int n = 0, last = 0;
  for (const Poly& p : s) {
    const int v = sign(eval(p, x));
    if (v == 0) continue;
    if (last != 0 && v != last) ++n;
    last = v;
  }
  return n;
}
// Distinct roots in (lo, hi], neither end a root.
inline int roots(const std::vector<Poly>& s, const mpq_class& lo, const mpq_class& hi) {
  return changes(s, lo) - changes(s, hi);
}

using PVec = std::array<Poly, 3>;
inline PVec moving(const Vec3& x0, const Vec3& x1) {
  PVec r;
  for (int d = 0; d < 3; ++d) {
    r[d] = {mpq_class(x0[d]), mpq_class(x1[d]) - mpq_class(x0[d])};
    trim(r[d]);
  }
  return r;
}
inline PVec sub(const PVec& a, const PVec& b) {
  return {add(a[0], b[0], -1), add(a[1], b[1], -1), add(a[2], b[2], -1)};
}
inline PVec cross(const PVec& a, const PVec& b) {
  return {add(mul(a[1], b[2]), mul(a[2], b[1]), -1), add(mul(a[2], b[0]), mul(a[0], b[2]), -1),
          add(mul(a[0], b[1]), mul(a[1], b[0]), -1)};
}
inline Poly dot(const PVec& a, const PVec& b) {
  return add(add(mul(a[0], b[0]), mul(a[1], b[1])), mul(a[2], b[2]));
}

// The sign of g at the one root of the Sturm sequence `s` in (lo, hi): refined by bisection
// until g has no root on the interval; 0 when that never happens (g shares the root).
inline int sign_at_root(const Poly& g, const std::vector<Poly>& s, mpq_class lo, mpq_class hi) {
  if (g.empty()) return 0;
  const std::vector<Poly> gs = sturm(g);
  for (int it = 0; it < 200; ++it) {
    if (sign(eval(g, lo)) != 0 && sign(eval(g, hi)) != 0 && roots(gs, lo, hi) == 0)
      return sign(eval(g, lo));
    for (const int k : {1, 3, 2, 5, 4})  // a split point that is not a root of the cubic
    {
      const mpq_class mid = lo + (hi - lo) * k / 6;
      if (sign(eval(s[0], mid)) == 0) continue;
      if (roots(s, lo, mid) == 1)
        hi = mid;
      else
        lo = mid;
      break;
    }
  }
  return 0;
}

// Each root of the cubic d in (0, 1), isolated; nullopt when d is zero at 0 or 1 or everywhere.
inline std::optional<std::vector<std::array<mpq_class, 2>>> isolate(const Poly& d) {
  if (d.empty() || sign(eval(d, 0)) == 0 || sign(eval(d, 1)) == 0) return std::nullopt;
  const std::vector<Poly> s = sturm(d);
  std::vector<std::array<mpq_class, 2>> out, todo{{mpq_class(0), mpq_class(1)}};
  while (!todo.empty()) {
    const auto [lo, hi] = todo.back();
    todo.pop_back();
    const int n = roots(s, lo, hi);
    if (n == 0) continue;
    if (n == 1) {
      out.push_back({lo, hi});
      continue;
    }
    for (const int k : {1, 2, 3, 5, 4}) {
      const mpq_class mid = lo + (hi - lo) * k / 7;
      if (sign(eval(d, mid)) == 0) continue;
      todo.push_back({lo, mid});
      todo.push_back({mid, hi});
      break;
    }
  }
  return out;
}

// Decides from the strict signs at each root: `inside` returns 1 (strictly meeting), −1
// (strictly apart) or 0 (undecided) for the root in (lo, hi).
template <class Inside>
std::optional<bool> decide(const Poly& d, Inside inside) {
  const auto isolated = isolate(d);
  if (!isolated) return std::nullopt;
  const std::vector<Poly> s = sturm(d);
  bool undecided = false;
  for (const auto& [lo, hi] : *isolated) {
    const int v = inside(s, lo, hi);
    if (v > 0) return true;
    if (v == 0) undecided = true;
  }
  if (undecided) return std::nullopt;
  return false;
}

/// Vertex–face, q = p, a, b, c at t = 0, then at t = 1.
inline std::optional<bool> vertex_face(const std::array<Vec3, 8>& q) {
  const PVec p = moving(q[0], q[4]), a = moving(q[1], q[5]), b = moving(q[2], q[6]),
             c = moving(q[3], q[7]);
  const PVec n = cross(sub(b, a), sub(c, a));
  const Poly d = dot(n, sub(p, a));
  // Inside the triangle: each edge sees p on the side of the face's normal.
  const std::array<Poly, 3> g = {dot(cross(sub(b, a), sub(p, a)), n),
                                 dot(cross(sub(c, b), sub(p, b)), n),
                                 dot(cross(sub(a, c), sub(p, c)), n)};
  return decide(d, [&](const std::vector<Poly>& s, const mpq_class& lo, const mpq_class& hi) {
    int all = 1;
    for (const Poly& gi : g) {
      const int v = sign_at_root(gi, s, lo, hi);
      if (v < 0) return -1;
      if (v == 0) all = 0;
    }
    return all;
  });
}

/// Edge–edge, q = a, b (first edge), c, d (second) at t = 0, then at t = 1: a proper crossing.
inline std::optional<bool> edge_edge(const std::array<Vec3, 8>& q) {
  const PVec a = moving(q[0], q[4]), b = moving(q[1], q[5]), c = moving(q[2], q[6]),
             e = moving(q[3], q[7]);
  const PVec u = sub(b, a), v = sub(e, c);
  const Poly d = dot(cross(u, sub(c, a)), sub(e, a));
  const PVec m = cross(u, v);  // the common plane's normal (zero for parallel edges)
  const Poly s1 = dot(cross(u, sub(c, a)), m), s2 = dot(cross(u, sub(e, a)), m);
  const Poly s3 = dot(cross(v, sub(a, c)), m), s4 = dot(cross(v, sub(b, c)), m);
  return decide(d, [&](const std::vector<Poly>& s, const mpq_class& lo, const mpq_class& hi) {
    const int v1 = sign_at_root(s1, s, lo, hi), v2 = sign_at_root(s2, s, lo, hi);
    const int v3 = sign_at_root(s3, s, lo, hi), v4 = sign_at_root(s4, s, lo, hi);
    if ((v1 * v2 > 0) || (v3 * v4 > 0)) return -1;  // one edge wholly on one side of the other
    if (v1 * v2 < 0 && v3 * v4 < 0) return 1;       // a proper crossing
    return 0;
  });
}

}  // namespace tc::reference
