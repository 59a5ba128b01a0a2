// The coplanarity determinant of a moving query (Dobritsa et al. eq. 13) in doubles, with
// certified error bounds, shared by the exact CCD's Bernstein test and the interval filter.
//
//   f(t) = det[u(t), v(t), w(t)],  u = P_i − P_o, v = P_j − P_o, w = P_k − P_o, each linear in t,
// is trilinear in (u, v, w), so in the Bernstein basis of [0, 1]
//   f(t) = Σ_k S_k (1 − t)^{3−k} t^k,  S_k = Σ of det[u_a, v_b, w_c] over a + b + c = k
// (a, b, c ∈ {0, 1}: the vectors at t = 0 or 1; S_k / C(3, k) are the Bernstein coefficients).
// Each det is computed in doubles as in Shewchuk's orient3d; its error, from the rounded
// differences (1 ulp each), the products and the sums, is below 8 ε times its permanent
// (the same sum with every term taken in absolute value; ε = 2⁻⁵³), and S_k's with its sum's
// rounding below 9 ε Σ permanents: E_k = 16 ε Σ permanents bounds it. The bounds hold while
// they stay in the normal range (`usable`), where no term's underflow is comparable to them.
#pragma once

#include <array>
#include <cmath>

#include "tetcontact/mesh/mesh.hpp"

namespace tc {

// y × z in doubles with the absolute products beside it, so that det[x, y, z] = x · (y × z)
// comes with its permanent |x| · (|y₁z₂| + |y₂z₁|, …): rounding in the products, the
// differences and the sums errs by at most 5 ε times the permanent, the rounded differences
// that make x, y, z by 3 ε more.
struct BoundedCross {
  Vec3 value, magnitude;
  double dot(const Vec3& x) const { return (x[0] * value[0] + x[1] * value[1]) + x[2] * value[2]; }
  double permanent(const Vec3& x) const {
    return (std::abs(x[0]) * magnitude[0] + std::abs(x[1]) * magnitude[1]) +
           std::abs(x[2]) * magnitude[2];
  }
};
inline BoundedCross cross_bounded(const Vec3& y, const Vec3& z) {
  const double p12 = y[1] * z[2], p21 = y[2] * z[1], p20 = y[2] * z[0], p02 = y[0] * z[2],
               p01 = y[0] * z[1], p10 = y[1] * z[0];
  return {Vec3(p12 - p21, p20 - p02, p01 - p10),
          Vec3(std::abs(p12) + std::abs(p21), std::abs(p20) + std::abs(p02),
               std::abs(p01) + std::abs(p10))};
}

// An error bound e is usable when it is neither overflowed nor in the subnormal range.
inline bool usable_bound(double e) {
  return e < 1e300 && (e == 0 || e >= 1e-280);
}

/// S_k ± E_k, k = 0 … 3, of the query q (points 0–3 at t = 0, 4–7 at t = 1).
struct Coplanarity {
  std::array<double, 4> S{}, E{};
  bool usable() const {
    return usable_bound(E[0]) && usable_bound(E[1]) && usable_bound(E[2]) && usable_bound(E[3]);
  }
};
inline Coplanarity coplanarity(const std::array<Vec3, 8>& q, int o, int i, int j, int k) {
  constexpr double eps = 0x1p-53;
  Vec3 u[2], v[2], w[2];
  for (int s = 0; s < 2; ++s) {
    u[s] = q[4 * s + i] - q[4 * s + o];
    v[s] = q[4 * s + j] - q[4 * s + o];
    w[s] = q[4 * s + k] - q[4 * s + o];
  }
  // Each cross product v_b × w_c serves both u's.
  Coplanarity c;
  for (int b = 0; b < 2; ++b)
    for (int d = 0; d < 2; ++d) {
      const BoundedCross cr = cross_bounded(v[b], w[d]);
      for (int a = 0; a < 2; ++a) {
        c.S[a + b + d] += cr.dot(u[a]);
        c.E[a + b + d] += 16 * eps * cr.permanent(u[a]);
      }
    }
  return c;
}

}  // namespace tc
