#include "tetcontact/app/float_ccd.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace tc {

namespace {

// Whether p lies in triangle (a, b, c) assumed coplanar with it, up to a relative tolerance.
bool in_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 n = (b - a).cross(c - a);
  const double nn = n.squaredNorm();
  if (nn == 0.0) return false;  // a degenerate face
  const double slack = 1e-12 * nn;
  return (b - a).cross(p - a).dot(n) >= -slack && (c - b).cross(p - b).dot(n) >= -slack &&
         (a - c).cross(p - c).dot(n) >= -slack;
}

}  // namespace

std::optional<double> vertex_face_ccd(const Vec3& p0, const Vec3& a0, const Vec3& b0,
                                      const Vec3& c0, const Vec3& p1, const Vec3& a1,
                                      const Vec3& b1, const Vec3& c1) {
  const auto at = [](const Vec3& x0, const Vec3& x1, double t) { return Vec3(x0 + t * (x1 - x0)); };
  const auto f = [&](double t) {
    const Vec3 a = at(a0, a1, t);
    return (at(b0, b1, t) - a).cross(at(c0, c1, t) - a).dot(at(p0, p1, t) - a);
  };
  const auto hit = [&](double t) {
    return in_triangle(at(p0, p1, t), at(a0, a1, t), at(b0, b1, t), at(c0, c1, t));
  };
  // f is a cubic: sample it at its own Bernstein-free partition (the roots of f' split [0,1]
  // into monotone pieces), then bisect each sign change.
  // Cubic coefficients from four samples.
  const double f0 = f(0.0), f13 = f(1.0 / 3.0), f23 = f(2.0 / 3.0), f1 = f(1.0);
  const double scale = std::max({std::abs(f0), std::abs(f13), std::abs(f23), std::abs(f1)});
  if (scale == 0.0) {  // coplanar all step: touching iff inside at some sampled time
    for (double t : {0.0, 0.25, 0.5, 0.75, 1.0})
      if (hit(t)) return t;
    return std::nullopt;
  }
  // Lagrange → monomial: f(t) = k3 t³ + k2 t² + k1 t + k0.
  const double k0 = f0;
  const double k3 = 4.5 * (-f0 + 3 * f13 - 3 * f23 + f1);
  const double k2 = 4.5 * (2 * f0 - 5 * f13 + 4 * f23 - f1);
  const double k1 = f1 - k0 - k2 - k3;
  std::vector<double> splits{0.0};
  // Stationary points: 3 k3 t² + 2 k2 t + k1 = 0.
  const double qa = 3 * k3, qb = 2 * k2, qc = k1;
  if (std::abs(qa) > 1e-300) {
    const double disc = qb * qb - 4 * qa * qc;
    if (disc >= 0) {
      const double s = std::sqrt(disc);
      for (double t : {(-qb - s) / (2 * qa), (-qb + s) / (2 * qa)})
        if (t > 0 && t < 1) splits.push_back(t);
    }
  } else if (std::abs(qb) > 1e-300) {
    const double t = -qc / qb;
    if (t > 0 && t < 1) splits.push_back(t);
  }
  splits.push_back(1.0);
  std::sort(splits.begin(), splits.end());
  const double zero = 1e-14 * scale;
  for (std::size_t i = 0; i + 1 < splits.size(); ++i) {
    double lo = splits[i], hi = splits[i + 1];
    double flo = f(lo), fhi = f(hi);
    if (std::abs(flo) <= zero && hit(lo)) return lo;
    if ((flo > 0) == (fhi > 0) && std::abs(fhi) > zero) continue;
    for (int it = 0; it < 80 && hi - lo > 1e-15; ++it) {
      const double mid = 0.5 * (lo + hi), fm = f(mid);
      if ((fm > 0) == (flo > 0))
        lo = mid, flo = fm;
      else
        hi = mid;
    }
    // Check a small bracket around the root (the inside test at the root is the decision).
    for (double t : {hi, lo})
      if (hit(t)) return t;
  }
  return std::nullopt;
}

}  // namespace tc
