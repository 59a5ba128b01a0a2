#include "tetcontact/diagnostics/shield_equation.hpp"

#include <cmath>
#include <cstdio>
#include <numbers>

namespace tc {
namespace {

constexpr double k_ksi = 6.894757293168e6;  // Pa per ksi (1000 lbf/in²)

// The shot in the equation's units: cm, g/cm³, km/s, ksi.
struct Cgs {
  double d, v, c, tb, s, tw, sigma, rp, rb;
};
Cgs cgs(const WhippleShot& x) {
  return {x.diameter * 100.0,
          x.speed / 1000.0,
          std::cos(x.obliquity_deg * std::numbers::pi / 180.0),
          x.bumper_thickness * 100.0,
          x.standoff * 100.0,
          x.wall_thickness * 100.0,
          x.wall_yield / k_ksi,
          x.projectile_density / 1000.0,
          x.bumper_density / 1000.0};
}

}  // namespace

const char* shield_regime_name(ShieldRegime r) {
  switch (r) {
    case ShieldRegime::ballistic:
      return "ballistic";
    case ShieldRegime::shatter:
      return "shatter";
    case ShieldRegime::hypervelocity:
      return "hypervelocity";
  }
  return "?";
}

ShieldRegime christiansen_regime(const WhippleShot& shot) {
  const Cgs q = cgs(shot);
  const double vn = q.v * q.c;
  return vn <= 3.0   ? ShieldRegime::ballistic
         : vn >= 7.0 ? ShieldRegime::hypervelocity
                     : ShieldRegime::shatter;
}

double christiansen_critical_diameter(const WhippleShot& shot) {
  const Cgs q = cgs(shot);
  const double vn = q.v * q.c;
  // The wall and bumper's resistance at low speed, and the hypervelocity part's factor.
  const double wall = q.tw * std::sqrt(q.sigma / 40.0) + q.tb;
  const double hyper = std::pow(q.tw, 2.0 / 3.0) * std::pow(q.rp, -1.0 / 3.0) *
                       std::pow(q.rb, -1.0 / 9.0) * std::cbrt(q.s) * std::cbrt(q.sigma / 70.0);
  double d_cm = 0.0;
  switch (christiansen_regime(shot)) {
    case ShieldRegime::ballistic:
      // d_c = [(t_w (σ/40)^0.5 + t_b) / (0.6 (cos θ)^(5/3) ρ_p^0.5 V^(2/3))]^(18/19)
      d_cm = std::pow(
          wall / (0.6 * std::pow(q.c, 5.0 / 3.0) * std::sqrt(q.rp) * std::pow(q.v, 2.0 / 3.0)),
          18.0 / 19.0);
      break;
    case ShieldRegime::hypervelocity:
      // d_c = 3.918 t_w^(2/3) ρ_p^(−1/3) ρ_b^(−1/9) V_n^(−2/3) S^(1/3) (σ/70)^(1/3)
      d_cm = 3.918 * hyper * std::pow(vn, -2.0 / 3.0);
      break;
    case ShieldRegime::shatter:
      // the line between the two: [...]^(18/19) (1.75 − V_n/4) + 1.071 [...] (V_n/4 − 0.75)
      d_cm = std::pow(wall / (1.248 * std::sqrt(q.rp) * q.c), 18.0 / 19.0) * (1.75 - vn / 4.0) +
             1.071 * hyper * (vn / 4.0 - 0.75);
      break;
  }
  return d_cm / 100.0;
}

ShieldEquationVerdict christiansen_verdict(const WhippleShot& shot) {
  ShieldEquationVerdict v;
  v.critical_diameter = christiansen_critical_diameter(shot);
  v.regime = christiansen_regime(shot);
  v.perforated = shot.diameter > v.critical_diameter;
  return v;
}

std::string describe(const WhippleShot& shot, const ShieldEquationVerdict& v) {
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "Christiansen's equation: critical diameter %.2f mm at %.2f km/s, %.0f deg "
                "(%s): a %.2f mm sphere %s the wall",
                v.critical_diameter * 1e3, shot.speed / 1e3, shot.obliquity_deg,
                shield_regime_name(v.regime), shot.diameter * 1e3,
                v.perforated ? "perforates" : "does not perforate");
  return buf;
}

}  // namespace tc
