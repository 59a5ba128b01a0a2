// The certified filter's polynomials in doubles with error bounds (bounded_poly.hpp) against the
// same polynomials in exact rationals: every exact coefficient lies within its bound.
#include <gtest/gtest.h>

#include <gmpxx.h>

#include <array>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "reference_ccd.hpp"
#include "tetcontact/narrowphase/bounded_poly.hpp"

using namespace tc;

namespace {

// The same expressions twice: in doubles with bounds, and exactly.
using reference::mul;
struct ExactVec {
  reference::Poly x, y, z;
};
ExactVec sub(const ExactVec& a, const ExactVec& b) {
  return {reference::add(a.x, b.x, -1), reference::add(a.y, b.y, -1), reference::add(a.z, b.z, -1)};
}
ExactVec cross(const ExactVec& a, const ExactVec& b) {
  return {reference::add(mul(a.y, b.z), mul(a.z, b.y), -1),
          reference::add(mul(a.z, b.x), mul(a.x, b.z), -1),
          reference::add(mul(a.x, b.y), mul(a.y, b.x), -1)};
}
reference::Poly dot(const ExactVec& a, const ExactVec& b) {
  return reference::add(reference::add(mul(a.x, b.x), mul(a.y, b.y)), mul(a.z, b.z));
}
reference::Poly moving(double x0, double x1) {
  return {mpq_class(x0), mpq_class(x1) - mpq_class(x0)};
}

// The number of coefficients of the bounded poly whose exact value lies outside v ± e (widened
// by 2⁻⁴⁵ and 2⁻¹⁰⁰⁰ as the filter widens it), and how many were compared.
struct Count {
  long outside = 0, compared = 0;
};
void compare(const BoundedPoly& b, const reference::Poly& exact, Count& c) {
  for (int k = 0; k < 5; ++k) {
    const mpq_class x = k < static_cast<int>(exact.size()) ? exact[k] : mpq_class(0);
    const double v = k < b.n ? b.v[k] : 0.0, e = k < b.n ? b.e[k] : 0.0;
    const mpq_class bound(e * (1.0 + 0x1p-45) + 0x1p-1000);
    ++c.compared;
    if (abs(x - mpq_class(v)) > bound) ++c.outside;
  }
}

}  // namespace

// Queries of four points moving over a step, four kinds: generic ones; nearly coplanar ones far
// from the origin (large offsets, small differences: the slopes and differences round and the
// determinant cancels); motions whose ends differ by a few ulps; and points whose x is of order
// 2⁹⁹ and y, z of 2⁻⁵³⁶ and 2⁻⁵⁴⁰ (the cross products' y z terms fall below the normal range, and
// the dot product multiplies their rounding by 2⁹⁹). For each, the coplanarity
// determinant det[b − a, c − a, d − a] and the edges' four inside orientations
// ((b − a) × (c − a))·m, m = (b − a) × (d − c), as the filter forms them. Without the bounds'
// propagation through the products (only each product's own rounding kept) exact coefficients
// fall outside, and so they do without the products' 2⁻¹⁰²² (test run with each change: it
// fails).
TEST(BoundedPoly, EveryExactCoefficientLiesWithinItsBound) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  std::uniform_int_distribution<int> scale(0, 4);
  Count c;
  for (int q = 0; q < 4000; ++q) {
    const int kind = q % 4;
    const double offset = kind == 1 ? 1e6 : 0.0;
    std::array<double, 24> x{};
    for (int k = 0; k < 12; ++k) {
      if (kind == 3) {  // x of order 2⁹⁹, y and z of 2⁻⁵³⁶ and 2⁻⁵⁴⁰: y z underflows
        const int e = (k % 3 == 0 ? 99 : k % 3 == 1 ? -536 : -540) - scale(rng);
        x[k] = std::ldexp(u(rng), e);
        x[12 + k] = rng() % 2 ? x[k] : x[k] + std::ldexp(u(rng), e);
        continue;
      }
      x[k] = offset + (kind == 1 ? 1e-3 : 1.0) * u(rng);
      x[12 + k] = kind == 2 ? x[k] + 4.0 * std::abs(x[k]) * 0x1p-52 * u(rng)
                            : x[k] + (kind == 1 ? 1e-4 : 0.5) * u(rng);
    }
    std::array<BoundedVec, 4> bp;
    std::array<ExactVec, 4> ep;
    for (int n = 0; n < 4; ++n) {
      bp[n] = {BoundedPoly::moving(x[3 * n], x[12 + 3 * n]),
               BoundedPoly::moving(x[3 * n + 1], x[12 + 3 * n + 1]),
               BoundedPoly::moving(x[3 * n + 2], x[12 + 3 * n + 2])};
      ep[n] = {moving(x[3 * n], x[12 + 3 * n]), moving(x[3 * n + 1], x[12 + 3 * n + 1]),
               moving(x[3 * n + 2], x[12 + 3 * n + 2])};
    }
    compare(dot(bp[3] - bp[0], cross(bp[1] - bp[0], bp[2] - bp[0])),
            dot(sub(ep[3], ep[0]), cross(sub(ep[1], ep[0]), sub(ep[2], ep[0]))), c);
    const BoundedVec bu = bp[1] - bp[0], bv = bp[3] - bp[2], bm = cross(bu, bv);
    const ExactVec eu = sub(ep[1], ep[0]), ev = sub(ep[3], ep[2]), em = cross(eu, ev);
    compare(dot(cross(bu, bp[2] - bp[0]), bm), dot(cross(eu, sub(ep[2], ep[0])), em), c);
    compare(dot(cross(bu, bp[3] - bp[0]), bm), dot(cross(eu, sub(ep[3], ep[0])), em), c);
    compare(dot(cross(bv, bp[0] - bp[2]), bm), dot(cross(ev, sub(ep[0], ep[2])), em), c);
    compare(dot(cross(bv, bp[1] - bp[2]), bm), dot(cross(ev, sub(ep[1], ep[2])), em), c);
  }
  RecordProperty("compared", std::to_string(c.compared));
  EXPECT_EQ(c.compared, 4000L * 5 * 5);
  EXPECT_EQ(c.outside, 0);
}

// The bounds are not vacuous: on generic queries each is within a few thousand roundings of the
// coefficient's size (a bound of every magnitude would make the filter decide nothing).
TEST(BoundedPoly, BoundsAreAFewRoundingsOfTheValues) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int q = 0; q < 200; ++q) {
    std::array<BoundedVec, 4> p;
    for (BoundedVec& v : p)
      v = {BoundedPoly::moving(u(rng), u(rng)), BoundedPoly::moving(u(rng), u(rng)),
           BoundedPoly::moving(u(rng), u(rng))};
    const BoundedPoly f = dot(p[3] - p[0], cross(p[1] - p[0], p[2] - p[0]));
    double size = 0.0, bound = 0.0;
    for (int k = 0; k < f.n; ++k) {
      size = std::max(size, std::abs(f.v[k]));
      bound = std::max(bound, f.e[k]);
    }
    EXPECT_GT(bound, 0.0);
    EXPECT_LT(bound, 4096 * 0x1p-53 * std::max(size, 1e-3)) << "query " << q;
  }
}
