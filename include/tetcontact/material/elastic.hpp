// Linear elasticity in rate form, split into pressure and deviator so that plasticity (a
// radial return on the deviator) and an equation of state (the pressure) slot in later.
#pragma once

#include <cmath>
#include <string>

#include "tetcontact/mesh/mesh.hpp"

namespace tc {

struct Material {
  std::string name;
  double density = 0.0;         // ρ, kg/m³
  double youngs_modulus = 0.0;  // E, Pa
  double poisson_ratio = 0.0;   // ν

  double bulk_modulus() const { return youngs_modulus / (3.0 * (1.0 - 2.0 * poisson_ratio)); }
  double shear_modulus() const { return youngs_modulus / (2.0 * (1.0 + poisson_ratio)); }
  /// Dilatational (P-wave) speed c = sqrt((K + 4G/3) / ρ), the speed the CFL condition uses.
  double wave_speed() const {
    return std::sqrt((bulk_modulus() + 4.0 / 3.0 * shear_modulus()) / density);
  }
};

/// Symmetric tensor stored as (xx, yy, zz, xy, yz, xz): VTK's component order.
using Sym6 = std::array<double, 6>;

inline Mat3 to_mat3(const Sym6& s) {
  Mat3 m;
  m << s[0], s[3], s[5], s[3], s[1], s[4], s[5], s[4], s[2];
  return m;
}
inline Sym6 to_sym6(const Mat3& m) {
  return {m(0, 0),
          m(1, 1),
          m(2, 2),
          0.5 * (m(0, 1) + m(1, 0)),
          0.5 * (m(1, 2) + m(2, 1)),
          0.5 * (m(0, 2) + m(2, 0))};
}

/// One explicit step of the hypoelastic law with the Jaumann rate.
///   D = sym(L), W = skew(L)            L: velocity gradient
///   s^{n+1} = s^n + τ (2G dev D + W s^n − s^n W)
///   p^{n+1} = p^n − τ K tr D
/// s: deviatoric stress, p: pressure (positive in compression), σ = s − p I.
inline void elastic_rate_update(const Material& mat, const Mat3& L, double tau, Mat3& s,
                                double& p) {
  const Mat3 D = 0.5 * (L + L.transpose());
  const Mat3 W = 0.5 * (L - L.transpose());
  const double trD = D.trace();
  const Mat3 devD = D - (trD / 3.0) * Mat3::Identity();
  s += tau * (2.0 * mat.shear_modulus() * devD + W * s - s * W);
  p -= tau * mat.bulk_modulus() * trD;
}

}  // namespace tc
