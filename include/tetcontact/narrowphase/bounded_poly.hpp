// Polynomials in t of degree ≤ 4 formed in plain doubles, each coefficient with a bound on its
// error carried through every operation (midpoint and radius), for the certified floating-point
// CCD filter (interval_ccd.cpp): the exact polynomial's coefficient k lies in v[k] ± e[k].
//
// An input's e is 0 (an exact double) or ε |v| (rounded once; ε = 2⁻⁵³: half an ulp is at most
// ε |v| for a normal result, and a difference below 2⁻¹⁰²¹ is exact); a sum's e is its terms' plus
// ε |v| (a sum that lands below the normal range is exact); a product's
//   |x| e_y + |y| e_x + e_x e_y + ε |v| + 2⁻¹⁰²²,
// since |XY − xy| ≤ |x| |Y − y| + |y| |X − x| + |X − x| |Y − y|, and a product that underflows
// is off by up to 2⁻¹⁰⁷⁵, which no relative term covers and later products would multiply by up
// to 2²⁰⁰: the 2⁻¹⁰²² covers it, and the underflows in computing the term's own bound (|x| e_y,
// |y| e_x, e_x e_y: with the product's, at most 2⁻¹⁰⁷³ in all), so that nothing absolute is left
// for a later product to scale up (sums below 2⁻¹⁰²¹ are exact). The bounds are computed in
// doubles on nonnegative numbers, at most about 35 roundings deep (e_x e_y compounds both
// shortfalls), so each may fall short of its exact value by a relative 2⁻⁴⁷ at most: a user
// widens them by 2⁻⁴⁵ before trusting them.
// Against interval ends (four products, their minimum and maximum, and a widening at every
// operation) about half the work.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>

namespace tc {

struct BoundedPoly {
  static constexpr double kEps = 0x1p-53;
  std::array<double, 5> v{}, e{};
  int n = 0;  // number of coefficients; those past n are 0, exact

  /// x0 + t (x1 − x0): a coordinate moving linearly over the step, its slope rounded once.
  static BoundedPoly moving(double x0, double x1) {
    BoundedPoly p;
    p.n = 2;
    p.v = {x0, x1 - x0, 0.0, 0.0, 0.0};
    p.e = {0.0, kEps * std::abs(x1 - x0), 0.0, 0.0, 0.0};
    return p;
  }
};

inline BoundedPoly sum(const BoundedPoly& x, const BoundedPoly& y, double sign) {
  BoundedPoly r;
  r.n = std::max(x.n, y.n);
  for (int k = 0; k < r.n; ++k) {
    r.v[k] = x.v[k] + sign * y.v[k];
    r.e[k] = x.e[k] + y.e[k] + BoundedPoly::kEps * std::abs(r.v[k]);
  }
  return r;
}
inline BoundedPoly operator+(const BoundedPoly& x, const BoundedPoly& y) {
  return sum(x, y, 1.0);
}
inline BoundedPoly operator-(const BoundedPoly& x, const BoundedPoly& y) {
  return sum(x, y, -1.0);
}
/// Degrees must add up to ≤ 4.
inline BoundedPoly operator*(const BoundedPoly& x, const BoundedPoly& y) {
  constexpr double eps = BoundedPoly::kEps;
  BoundedPoly r;
  r.n = x.n + y.n - 1;
  for (int i = 0; i < x.n; ++i)
    for (int j = 0; j < y.n; ++j) {
      const double p = x.v[i] * y.v[j];
      const double ep = std::abs(x.v[i]) * y.e[j] + std::abs(y.v[j]) * x.e[i] + x.e[i] * y.e[j] +
                        eps * std::abs(p) + 0x1p-1022;
      r.v[i + j] += p;
      r.e[i + j] += ep + eps * std::abs(r.v[i + j]);
    }
  return r;
}

/// A single value with its bound, the degree-0 case of the rules above.
struct Bounded {
  double v = 0.0, e = 0.0;
};
inline Bounded operator+(Bounded x, Bounded y) {
  const double v = x.v + y.v;
  return {v, x.e + y.e + BoundedPoly::kEps * std::abs(v)};
}
inline Bounded operator-(Bounded x, Bounded y) {
  const double v = x.v - y.v;
  return {v, x.e + y.e + BoundedPoly::kEps * std::abs(v)};
}
inline Bounded operator*(Bounded x, Bounded y) {
  const double v = x.v * y.v;
  return {v, std::abs(x.v) * y.e + std::abs(y.v) * x.e + x.e * y.e +
                 BoundedPoly::kEps * std::abs(v) + 0x1p-1022};
}
struct Bounded3 {
  std::array<Bounded, 3> x;
};
inline Bounded3 operator-(const Bounded3& a, const Bounded3& b) {
  return {{a.x[0] - b.x[0], a.x[1] - b.x[1], a.x[2] - b.x[2]}};
}
inline Bounded3 cross(const Bounded3& a, const Bounded3& b) {
  return {{a.x[1] * b.x[2] - a.x[2] * b.x[1], a.x[2] * b.x[0] - a.x[0] * b.x[2],
           a.x[0] * b.x[1] - a.x[1] * b.x[0]}};
}
inline Bounded dot(const Bounded3& a, const Bounded3& b) {
  return a.x[0] * b.x[0] + a.x[1] * b.x[1] + a.x[2] * b.x[2];
}

struct BoundedVec {
  BoundedPoly x, y, z;
};
inline BoundedVec operator-(const BoundedVec& a, const BoundedVec& b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
inline BoundedVec cross(const BoundedVec& a, const BoundedVec& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline BoundedPoly dot(const BoundedVec& a, const BoundedVec& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}

}  // namespace tc
