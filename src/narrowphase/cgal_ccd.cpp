// The CGAL oracle (cgal_ccd.hpp). The only file that includes CGAL's algebraic kernel.
#include "tetcontact/narrowphase/cgal_ccd.hpp"

#include <CGAL/Algebraic_kernel_d_1.h>
#include <CGAL/Gmpz.h>

#include <cmath>
#include <iterator>
#include <vector>

namespace tc {
namespace {

using AK = CGAL::Algebraic_kernel_d_1<CGAL::Gmpz>;
using Poly = AK::Polynomial_1;
using Root = AK::Algebraic_real_1;
using PVec = std::array<Poly, 3>;

// The smallest exponent of the coordinates' lowest set bits: every coordinate times
// 2^-exponent is an integer.
int lowest_exponent(const std::array<Vec3, 8>& q) {
  int e = 0;
  bool first = true;
  for (const Vec3& p : q)
    for (int d = 0; d < 3; ++d) {
      const double c = p[d];
      if (c == 0.0) continue;
      int exp;
      double m = std::frexp(c, &exp);  // c = m 2^exp, |m| in [0.5, 1)
      int k = exp;
      while (m != std::trunc(m)) m *= 2.0, --k;  // c = m 2^k, m an integer
      if (first || k < e) e = k, first = false;
    }
  return e;
}

CGAL::Gmpz integer(double c, int e) {  // c 2^-e, exactly
  if (c == 0.0) return CGAL::Gmpz(0);
  int exp;
  double m = std::frexp(c, &exp);
  int k = exp;
  while (m != std::trunc(m)) m *= 2.0, --k;
  CGAL::Gmpz z(m);  // |m| < 2^53: exact
  for (int s = e; s < k; ++s) z *= 2;
  return z;
}

// The point k of the query as polynomials in t: p(t) = p0 + t (p1 − p0).
PVec path(const std::array<Vec3, 8>& q, int k, int e) {
  const Poly t = CGAL::shift(Poly(1), 1);
  PVec out;
  for (int d = 0; d < 3; ++d) {
    const CGAL::Gmpz a = integer(q[k][d], e), b = integer(q[k + 4][d], e);
    out[d] = Poly(a) + t * Poly(b - a);
  }
  return out;
}

PVec sub(const PVec& a, const PVec& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
PVec cross(const PVec& a, const PVec& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
Poly dot(const PVec& a, const PVec& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
bool zero(const Poly& p) {
  return CGAL::is_zero(p);
}

// The real roots of p in [0, 1] (p not identically zero).
std::vector<Root> roots_in_step(const Poly& p) {
  static const AK ak;
  std::vector<std::pair<Root, AK::Multiplicity_type>> all;
  if (CGAL::degree(p) > 0) ak.solve_1_object()(p, std::back_inserter(all));
  std::vector<Root> out;
  const Root lo(0), hi(1);
  for (const auto& [r, m] : all)
    if (ak.compare_1_object()(r, lo) != CGAL::SMALLER &&
        ak.compare_1_object()(r, hi) != CGAL::LARGER)
      out.push_back(r);
  return out;
}

int sign_at(const Poly& p, const Root& r) {
  static const AK ak;
  if (zero(p)) return 0;
  return static_cast<int>(ak.sign_at_1_object()(p, r));
}

}  // namespace

// v meets the face when, at a root of D(t) = ((f1 − f0) × (f2 − f0))·(v − f0) in [0, 1], v lies
// in the closed triangle: with n = (f1 − f0) × (f2 − f0) ≠ 0 there, each edge's
// ((f_{i+1} − f_i) × (v − f_i))·n ≥ 0.
std::optional<bool> cgal_vertex_face_ccd(const std::array<Vec3, 8>& q) {
  const int e = lowest_exponent(q);
  const PVec v = path(q, 0, e), f0 = path(q, 1, e), f1 = path(q, 2, e), f2 = path(q, 3, e);
  const PVec n = cross(sub(f1, f0), sub(f2, f0));
  const Poly d = dot(n, sub(v, f0));
  if (zero(d)) return std::nullopt;  // coplanar all step
  const std::array<Poly, 3> inside = {dot(cross(sub(f1, f0), sub(v, f0)), n),
                                      dot(cross(sub(f2, f1), sub(v, f1)), n),
                                      dot(cross(sub(f0, f2), sub(v, f2)), n)};
  const Poly nn = dot(n, n);
  bool undecided = false;
  for (const Root& r : roots_in_step(d)) {
    if (sign_at(nn, r) == 0) {  // the face is degenerate at the root
      undecided = true;
      continue;
    }
    if (sign_at(inside[0], r) >= 0 && sign_at(inside[1], r) >= 0 && sign_at(inside[2], r) >= 0)
      return true;
  }
  if (undecided) return std::nullopt;
  return false;
}

// The edges meet when, at a root of D(t) = ((a1 − a0) × (b0 − a0))·(b1 − a0) in [0, 1], with
// n = (a1 − a0) × (b1 − b0) ≠ 0 there, each segment's ends are not strictly on one side of the
// other's line (in the common plane, signs taken against n).
std::optional<bool> cgal_edge_edge_ccd(const std::array<Vec3, 8>& q) {
  const int e = lowest_exponent(q);
  const PVec a0 = path(q, 0, e), a1 = path(q, 1, e), b0 = path(q, 2, e), b1 = path(q, 3, e);
  const PVec u = sub(a1, a0), w = sub(b1, b0);
  const Poly d = dot(cross(u, sub(b0, a0)), sub(b1, a0));
  if (zero(d)) return std::nullopt;  // coplanar all step
  const PVec n = cross(u, w);
  const Poly nn = dot(n, n);
  const Poly s0 = dot(cross(u, sub(b0, a0)), n), s1 = dot(cross(u, sub(b1, a0)), n);
  const Poly s2 = dot(cross(w, sub(a0, b0)), n), s3 = dot(cross(w, sub(a1, b0)), n);
  bool undecided = false;
  for (const Root& r : roots_in_step(d)) {
    if (sign_at(nn, r) == 0) {  // parallel at the root
      undecided = true;
      continue;
    }
    if (sign_at(s0, r) * sign_at(s1, r) <= 0 && sign_at(s2, r) * sign_at(s3, r) <= 0) return true;
  }
  if (undecided) return std::nullopt;
  return false;
}

}  // namespace tc
