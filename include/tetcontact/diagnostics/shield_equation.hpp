// Christiansen's ballistic limit equation of a Whipple shield: the critical diameter of an
// aluminium sphere (the largest the shield stops) at a speed and an obliquity, set beside the
// engine's own verdict on a shot (the case's `shield_equation:`).
//
//   E. L. Christiansen, "Design and performance equations for advanced meteoroid and debris
//   shields", Int. J. Impact Eng. 14 (1993) 145–156; NASA TP-2003-210788 (Christiansen,
//   "Meteoroid/Debris Shielding"), the Whipple shield's equations.
//
// In the equations' units (cm, g/cm³, km/s, ksi), with t_b the bumper's and t_w the wall's
// thickness, S the standoff, σ the wall's yield stress, ρ_p and ρ_b the projectile's and the
// bumper's densities, θ the obliquity and V_n = V cos θ:
//
//   ballistic, V_n ≤ 3 km/s:
//     d_c = [(t_w (σ/40)^0.5 + t_b) / (0.6 (cos θ)^(5/3) ρ_p^0.5 V^(2/3))]^(18/19)
//   hypervelocity, V_n ≥ 7 km/s:
//     d_c = 3.918 t_w^(2/3) ρ_p^(−1/3) ρ_b^(−1/9) V_n^(−2/3) S^(1/3) (σ/70)^(1/3)
//   shatter, 3 < V_n < 7 km/s: the straight line in V_n between the two at 3 and 7 km/s,
//     d_c = [(t_w (σ/40)^0.5 + t_b) / (1.248 ρ_p^0.5 cos θ)]^(18/19) (1.75 − V_n/4)
//         + 1.071 t_w^(2/3) ρ_p^(−1/3) ρ_b^(−1/9) S^(1/3) (σ/70)^(1/3) (V_n/4 − 0.75)
//
// (1.248 = 0.6 · 3^(2/3), 1.071 = 3.918 · 7^(−2/3).) The functions take and return SI units.
#pragma once

#include <string>

namespace tc {

/// A shot on a Whipple shield, SI units (m, m/s, kg/m³, Pa; the obliquity in degrees from the
/// bumper's normal).
struct WhippleShot {
  double diameter = 0.0;  // the projectile's
  double speed = 0.0;
  double obliquity_deg = 0.0;
  double bumper_thickness = 0.0;
  double standoff = 0.0;  // bumper's rear face to the wall's front face
  double wall_thickness = 0.0;
  double wall_yield = 0.0;  // the wall's yield stress σ of the equation
  double projectile_density = 0.0;
  double bumper_density = 0.0;
};

/// Which of the equation's three parts holds at a shot's normal speed V cos θ.
enum class ShieldRegime { ballistic, shatter, hypervelocity };
const char* shield_regime_name(ShieldRegime r);
ShieldRegime christiansen_regime(const WhippleShot& shot);

/// The critical diameter (m): a sphere larger than it perforates the wall, by the equation.
double christiansen_critical_diameter(const WhippleShot& shot);

/// What the equation says of a shot, for the run's output.
struct ShieldEquationVerdict {
  double critical_diameter = 0.0;  // m
  ShieldRegime regime = ShieldRegime::ballistic;
  bool perforated = false;  // diameter > critical_diameter
};
ShieldEquationVerdict christiansen_verdict(const WhippleShot& shot);

/// One line a person reads: "Christiansen's equation: critical diameter 2.18 mm at 5.00 km/s,
/// 30 deg (shatter): a 3.00 mm sphere perforates the wall".
std::string describe(const WhippleShot& shot, const ShieldEquationVerdict& v);

}  // namespace tc
