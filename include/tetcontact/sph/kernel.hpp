// The SPH kernel: Monaghan and Lattanzio's cubic B-spline in three dimensions (J. J. Monaghan,
// J. C. Lattanzio, Astron. Astrophys. 149, 135, 1985), with q = r / h:
//
//   W(r, h) = 1/(π h³) · { 1 − 3/2 q² + 3/4 q³   0 ≤ q < 1
//                        { 1/4 (2 − q)³           1 ≤ q < 2
//                        { 0                      q ≥ 2
//
// normalised (∫ W dV = 1) with compact support 2h; dW/dr is continuous, W'' too.
#pragma once

#include <cmath>
#include <numbers>

#include "tetcontact/mesh/mesh.hpp"

namespace tc::sph {

/// The kernel reaches r = k_support h.
inline constexpr double k_support = 2.0;

/// W(r, h).
inline double kernel(double r, double h) {
  const double q = r / h, sigma = 1.0 / (std::numbers::pi * h * h * h);
  if (q < 1.0) return sigma * (1.0 - 1.5 * q * q + 0.75 * q * q * q);
  if (q < 2.0) {
    const double t = 2.0 - q;
    return sigma * 0.25 * t * t * t;
  }
  return 0.0;
}

/// dW/dr at (r, h): ≤ 0 everywhere, 0 at r = 0 and beyond 2h.
inline double kernel_slope(double r, double h) {
  const double q = r / h, sigma = 1.0 / (std::numbers::pi * h * h * h * h);
  if (q < 1.0) return sigma * (-3.0 * q + 2.25 * q * q);
  if (q < 2.0) {
    const double t = 2.0 - q;
    return sigma * -0.75 * t * t;
  }
  return 0.0;
}

/// ∇_i W(|x_i − x_j|, h) for r = x_i − x_j: dW/dr · r / |r| (zero at r = 0). Antisymmetric to
/// the bit: r and −r give gradients of opposite sign exactly.
inline Vec3 kernel_gradient(const Vec3& r, double h) {
  const double d = r.norm();
  if (!(d > 0.0)) return Vec3::Zero();
  return (kernel_slope(d, h) / d) * r;
}

}  // namespace tc::sph
