// Materials: hypoelastic-plastic solid (Jaumann rate, von Mises, linear isotropic hardening)
// with a pressure from an equation of state (linear, Mie–Grüneisen with a linear Us–up
// Hugoniot, or Tillotson's for expanded and vaporising states). Dobritsa et al., "Основные
// соотношения": Prandtl–Reuss flow for impact Mach number M0 ≤ 0.75, a hydrodynamic model with a
// richer equation of state for 0.75 < M0 < 1.5.
//
// Each model is a small pure function; the element kernel (solver/element.cpp) calls them.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

#include "tetcontact/mesh/mesh.hpp"

namespace tc {

enum class EosKind { linear, mie_gruneisen, tillotson };

/// How the yield stress evolves: bilinear, σy = σy0 + H ε̄p (yield_stress,
/// hardening_modulus), Johnson–Cook, or Steinberg–Guinan.
enum class StrengthModel { bilinear, johnson_cook, steinberg_guinan };

/// Johnson–Cook (G. R. Johnson, W. H. Cook, 7th Int. Symp. Ballistics, The Hague, 1983):
///   σy = (A + B ε̄pⁿ) (1 + C ln ε̇*) (1 − T*ᵐ),
///   ε̇* = max(ε̇p / ε̇0, 1)  (no rate softening below the reference rate),
///   T* = (T − T_room) / (T_melt − T_room), clamped to [0, 1]: σy = 0 at and above melt.
struct JohnsonCook {
  double a = 0.0, b = 0.0, n = 1.0;  // Pa, Pa, –
  double c = 0.0;                    // rate sensitivity
  double reference_rate = 1.0;       // ε̇0, 1/s
  double m = 1.0;                    // thermal softening exponent
  double room_temperature = 293.0;   // K
  double melt_temperature = 0.0;     // K (0: no thermal softening)
};

/// Steinberg–Guinan (D. J. Steinberg, S. G. Cochran, M. W. Guinan, J. Appl. Phys. 51, 1498,
/// 1980), with η = ρ/ρ0 and P the pressure (compression > 0):
///   G(P, T) = G0 [1 + A max(P, 0) η^(−1/3) − B (T − T_ref)],
///   Y = min(Y0 [1 + β (ε̄p + εi)]ⁿ, Ymax) · G(P, T) / G0,
/// and melt by the modified Lindemann law
///   T_m(η) = T_m0 exp(2a (1 − 1/η)) η^(2 (Γ0 − a − 1/3)):
/// at or above T_m, G = Y = 0 (no deviatoric stress). A = G'_P/G0 (1/Pa), B = −G'_T/G0 (1/K).
/// The pressure enters only in compression (a tensile pressure would lower G below G0 without
/// the law saying so; Steinberg fitted it to compression).
struct SteinbergGuinan {
  double y0 = 0.0, ymax = 0.0;           // Pa
  double beta = 0.0, n = 1.0;            // hardening
  double initial_strain = 0.0;           // εi
  double a_pressure = 0.0;               // A, 1/Pa
  double b_temperature = 0.0;            // B, 1/K
  double reference_temperature = 300.0;  // T_ref, K
  double melt_temperature = 0.0;         // T_m0, K (0: no melt)
  double gamma0 = 0.0, a = 0.0;          // Lindemann's Γ0 and a
};

/// Johnson–Cook ductile failure (G. R. Johnson, W. H. Cook, Eng. Fract. Mech. 21, 31, 1985):
/// damage accumulates with the plastic strain as
///   D = Σ Δε̄p / ε_f,   ε_f = [D1 + D2 exp(D3 σ*)] [1 + D4 ln ε̇*] [1 + D5 T*],
/// σ* = σ_m / σ_eq the stress triaxiality (mean stress over von Mises, tension > 0),
/// ε̇* = max(ε̇p / ε̇0, 1), T* = (T − T_room) / (T_melt − T_room) clamped to [0, 1]; the cell
/// fails at D = 1 (it is then eroded: turned into a particle). ε_f is floored at min_strain (a
/// set with D1 < 0 gives a negative ε_f at high triaxiality).
struct JohnsonCookFailure {
  double d1 = 0.0, d2 = 0.0, d3 = 0.0, d4 = 0.0, d5 = 0.0;
  double reference_rate = 1.0;    // ε̇0, 1/s
  double room_temperature = 0.0;  // K (0: the strength law's reference temperature)
  double melt_temperature = 0.0;  // K (0: the strength law's; none: no temperature term)
  double min_strain = 0.01;       // floor of ε_f
};

/// ε_f of Johnson–Cook's failure law at triaxiality σ*, plastic strain rate ε̇p and
/// temperature T.
inline double johnson_cook_failure_strain(const JohnsonCookFailure& f, double triaxiality,
                                          double rate, double temperature) {
  const double stress = f.d1 + f.d2 * std::exp(std::min(f.d3 * triaxiality, 50.0));
  const double star = rate / f.reference_rate;
  const double rate_factor = star > 1.0 ? 1.0 + f.d4 * std::log(star) : 1.0;
  double thermal = 1.0;
  if (f.melt_temperature > f.room_temperature) {
    const double ts =
        (temperature - f.room_temperature) / (f.melt_temperature - f.room_temperature);
    thermal = 1.0 + f.d5 * std::clamp(ts, 0.0, 1.0);
  }
  return std::max(stress * rate_factor * thermal, f.min_strain);
}

/// Tillotson (J. H. Tillotson, "Metallic equations of state for hypervelocity impact", General
/// Atomic GA-3216, 1962), with η = ρ/ρ0, μ = η − 1, e the specific internal energy and
/// ω = 1 + e/(E0 η²):
///   compressed (μ ≥ 0) or cold (e ≤ E_iv):  p_c = (a + b/ω) ρ e + A μ + B μ²,
///   expanded and hot (μ < 0, e ≥ E_cv):    p_e = a ρ e + [b ρ e/ω + A μ exp(−β z)] exp(−α z²),
///                                          z = ρ0/ρ − 1,
///   between (μ < 0, E_iv < e < E_cv):      p = [(e − E_iv) p_e + (E_cv − e) p_c]/(E_cv − E_iv).
/// Far expanded the hot branch tends to the gas a ρ e, where a Mie–Grüneisen state keeps
/// p = K μ + Γ0 ρ0 e whatever its density. ω takes e ≥ 0 (a cell below its reference energy
/// has p_c linear in e).
struct Tillotson {
  double a = 0.0, b = 0.0;          // –
  double big_a = 0.0, big_b = 0.0;  // A, B, Pa
  double e0 = 0.0;                  // E0, J/kg
  double e_iv = 0.0, e_cv = 0.0;    // incipient and complete vaporisation energies, J/kg
  double alpha = 0.0, beta = 0.0;   // –
};

struct Material {
  std::string name;
  double density = 0.0;        // ρ0, kg/m³
  double shear_modulus = 0.0;  // G, Pa
  double bulk_modulus = 0.0;   // K, Pa (linear EOS; ρ0 c0² for Mie–Grüneisen, A for Tillotson)
  // Strength: plastic when yield_stress > 0 (von Mises, σy = σy0 + H ε̄p), or by Johnson–Cook.
  StrengthModel strength = StrengthModel::bilinear;
  double yield_stress = 0.0;       // σy0, Pa
  double hardening_modulus = 0.0;  // H, Pa
  JohnsonCook johnson_cook;
  SteinbergGuinan steinberg_guinan;
  // The plastic strain the metal carries before the run (its cold work, ε̄p0): every law's
  // hardening reads ε̄p0 + ε̄p (Steinberg–Guinan's own εi adds to it). ε̄p itself, its output,
  // erosion by strain and ductile damage count the run's strain alone.
  double initial_plastic_strain = 0.0;
  // Temperature, tracked per tet when specific_heat > 0: heated by the viscous
  // (shock) work and by the fraction taylor_quinney of the plastic work.
  double specific_heat = 0.0;        // c_v, J/(kg K)
  double taylor_quinney = 0.9;       // χ
  double initial_temperature = 0.0;  // K; 0: Johnson–Cook's room temperature (or 293 K)
  // Equation of state.
  EosKind eos = EosKind::linear;
  double c0 = 0.0;      // bulk sound speed, m/s (Mie–Grüneisen)
  double s = 0.0;       // Us = c0 + s up
  double gamma0 = 0.0;  // Grüneisen coefficient Γ0
  Tillotson tillotson;
  // Failure (Dobritsa et al., used when the case's fracture stage is on): a cell whose largest
  // tensile principal stress exceeds σ* is damaged (it then resists only volumetric
  // compression); a damaged cell loosened past χ = 1 − V0/V > χ* is destroyed (no pressure).
  double spall_strength = 0.0;    // σ*, Pa; 0: the material does not spall
  double loosening_limit = 0.03;  // χ*
  // Erosion by strain (a hydrocode safeguard; needs fracture with particles): a cell
  // whose equivalent plastic strain reaches this becomes a particle. 0: off.
  double erosion_plastic_strain = 0.0;
  // Ductile failure (needs fracture with particles): Johnson–Cook's damage D, a cell
  // eroded at D = 1. Off unless ductile_failure is set; the constants may come from a library.
  bool ductile_failure = false;
  // Whether damage accrues where the law's own ε_f is at or below its floor (min_strain), outside
  // the set's fit: off, tension there is left to the spall strength.
  bool ductile_failure_at_floor = true;
  JohnsonCookFailure johnson_cook_failure;

  bool plastic() const { return strength != StrengthModel::bilinear || yield_stress > 0.0; }
  bool thermal() const { return specific_heat > 0.0; }
  /// The temperature a tet starts at.
  double start_temperature() const {
    if (initial_temperature > 0.0) return initial_temperature;
    if (strength == StrengthModel::johnson_cook) return johnson_cook.room_temperature;
    if (strength == StrengthModel::steinberg_guinan) return steinberg_guinan.reference_temperature;
    return 293.0;
  }
  /// Young's modulus and Poisson's ratio from G and K.
  double youngs_modulus() const {
    return 9.0 * bulk_modulus * shear_modulus / (3.0 * bulk_modulus + shear_modulus);
  }
  double poisson_ratio() const {
    return (3.0 * bulk_modulus - 2.0 * shear_modulus) /
           (2.0 * (3.0 * bulk_modulus + shear_modulus));
  }
  /// Dilatational (P-wave) speed at the reference state, sqrt((K + 4G/3) / ρ0).
  double wave_speed() const {
    return std::sqrt((bulk_modulus + 4.0 / 3.0 * shear_modulus) / density);
  }
  /// Bulk sound speed at the reference state, sqrt(K / ρ0): the C0 of the impact Mach number.
  double bulk_sound_speed() const { return std::sqrt(bulk_modulus / density); }
};

/// G and K from Young's modulus and Poisson's ratio.
inline void set_elastic_constants(Material& m, double youngs, double poisson) {
  m.shear_modulus = youngs / (2.0 * (1.0 + poisson));
  m.bulk_modulus = youngs / (3.0 * (1.0 - 2.0 * poisson));
}

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

/// Von Mises equivalent stress of a deviator s: sqrt(3/2 s:s) (the yield stress on the yield
/// surface).
inline double von_mises(const Sym6& s) {
  const Mat3 m = to_mat3(s);
  return std::sqrt(1.5 * m.cwiseProduct(m).sum());
}

/// Objective rotation of the deviatoric stress over a step (Hughes–Winget):
///   s ← Q s Qᵀ,  Q = (I − τW/2)⁻¹ (I + τW/2),
/// which is exactly orthogonal for a skew W (the spin), so the principal values are kept to
/// round-off. With ω the axial vector of A = τW/2 (|ω| = θ): Q = I + 2 (A + A²) / (1 + θ²).
inline Mat3 jaumann_rotation(const Mat3& W, double tau) {
  const Mat3 A = 0.5 * tau * W;
  const double theta2 = A(2, 1) * A(2, 1) + A(0, 2) * A(0, 2) + A(1, 0) * A(1, 0);
  return Mat3::Identity() + (2.0 / (1.0 + theta2)) * (A + A * A);
}

/// The Johnson–Cook yield stress at plastic strain eps, plastic strain rate rate (1/s) and
/// temperature T (K).
inline double johnson_cook_yield(const JohnsonCook& jc, double eps, double rate, double T) {
  double thermal = 1.0;
  if (jc.melt_temperature > jc.room_temperature) {
    const double ts = (T - jc.room_temperature) / (jc.melt_temperature - jc.room_temperature);
    if (ts >= 1.0) return 0.0;  // molten
    if (ts > 0.0) thermal = 1.0 - std::pow(ts, jc.m);
  }
  const double strain = jc.b > 0.0 ? jc.a + jc.b * std::pow(std::max(eps, 0.0), jc.n) : jc.a;
  const double star = rate / jc.reference_rate;
  const double rate_factor = star > 1.0 ? 1.0 + jc.c * std::log(star) : 1.0;
  return strain * rate_factor * thermal;
}

/// Steinberg–Guinan's melt temperature at compression η = ρ/ρ0 (modified Lindemann law).
inline double steinberg_melt_temperature(const SteinbergGuinan& sg, double eta) {
  return sg.melt_temperature * std::exp(2.0 * sg.a * (1.0 - 1.0 / eta)) *
         std::pow(eta, 2.0 * (sg.gamma0 - sg.a - 1.0 / 3.0));
}
/// A lower bound of Steinberg–Guinan's melt temperature without its exp and pow: with
/// e = 2 (γ0 − a − 1/3) ≥ 0 and a ≥ 0, ln η ≥ 1 − 1/η gives
///   ln T_m ≥ ln T_m0 + (2a + e)(1 − 1/η),  and exp(x) ≥ 1 + x,
/// so T_m ≥ T_m0 [1 + (2a + e)(1 − 1/η)] (less 1e-9 of it for round-off). 0 where the law's
/// constants do not allow the bound.
inline double steinberg_melt_lower_bound(const SteinbergGuinan& sg, double eta) {
  const double e = 2.0 * (sg.gamma0 - sg.a - 1.0 / 3.0);
  if (!(e >= 0.0 && sg.a >= 0.0)) return 0.0;
  return sg.melt_temperature * (1.0 + (2.0 * sg.a + e) * (1.0 - 1.0 / eta)) * (1.0 - 1e-9);
}
/// The state-dependent part of a step's strength: the shear modulus G (G0 but for
/// Steinberg–Guinan), and for Steinberg–Guinan the melt temperature T_m(η) (0: no melt law;
/// NaN: not computed, T lies below its lower bound) and the pressure factor
/// 1 + A max(P, 0) η^(−1/3), so that G = G0 [factor − B (T − T_ref)], 0 at or above melt and
/// never negative.
struct StrengthState {
  double g = 0.0;
  double melt = 0.0;
  double pressure_factor = 1.0;
  double eta = 1.0;  // the compression ρ/ρ0 it was computed at
};
inline StrengthState strength_state(const Material& m, double p, double T, double eta) {
  StrengthState st;
  st.g = m.shear_modulus;
  st.eta = eta;
  if (m.strength != StrengthModel::steinberg_guinan) return st;
  const SteinbergGuinan& sg = m.steinberg_guinan;
  // No cube root where it is multiplied by zero (p ≤ 0: the factor is 1; a NaN goes through).
  st.pressure_factor = p <= 0.0 ? 1.0 : 1.0 + sg.a_pressure * p / std::cbrt(eta);
  if (sg.melt_temperature > 0.0)
    st.melt = T < steinberg_melt_lower_bound(sg, eta) ? std::numeric_limits<double>::quiet_NaN()
                                                      : steinberg_melt_temperature(sg, eta);
  const bool molten = st.melt > 0.0 && T >= st.melt;  // false for NaN
  st.g = molten ? 0.0
                : m.shear_modulus * std::max(st.pressure_factor -
                                                 sg.b_temperature * (T - sg.reference_temperature),
                                             0.0);
  return st;
}

/// Steinberg–Guinan's work-hardened yield min(Y0 [1 + β (ε̄p + εi)]ⁿ, Ymax), before the G/G0
/// scaling; slope: its derivative in ε̄p (0 on the cap).
inline double steinberg_hardening(const SteinbergGuinan& sg, double eps, double& slope) {
  const double base = 1.0 + sg.beta * (std::max(eps, 0.0) + sg.initial_strain);
  const double y = sg.y0 * std::pow(base, sg.n);
  if (sg.ymax > 0.0 && y >= sg.ymax) {
    slope = 0.0;
    return sg.ymax;
  }
  slope = sg.n * sg.beta * y / base;
  return y;
}
/// The shear modulus at pressure p, temperature T and compression η: G0 but for
/// Steinberg–Guinan.
inline double shear_modulus_at(const Material& m, double p, double T, double eta) {
  return strength_state(m, p, T, eta).g;
}

/// The plastic part of one step's radial return, from the trial von Mises stress eq:
/// Δε̄p ≥ 0 and the yield stress at the end of the step, on which the returned stress lies
/// (eq − 3G Δε̄p = σy). Bilinear: closed form,
///   Δε̄p = (eq − σy0 − H ε̄p) / (3G + H).
/// Johnson–Cook and Steinberg–Guinan: σy depends on Δε̄p through the hardening, (JC) the rate
/// Δε̄p/τ, and the step's heating, so the return solves the scalar equation
///   f(Δ) = eq − 3G Δ − σy(ε̄p + Δ, Δ/τ, T + χ (eq − 3G Δ) Δ / (ρ c_v)) = 0
/// (the heating by the plastic work at the end-of-step yield, which is eq − 3G Δ at the root)
/// on the bracket f(0) > 0 ≥ f(eq/3G), by Newton's method in ln Δ with the analytic slope, kept
/// in the bracket (bisection when a step would leave it), to round-off: the yield is not lagged.
/// G is the shear modulus of the step (Steinberg–Guinan's G(P, T) at the start of the step).
/// temperature: the tet's at the start of the step; rho: its density; pressure: its pressure at
/// the start of the step (Steinberg–Guinan).
struct PlasticIncrement {
  double dplastic = 0.0;
  /// σy at the end of the step; below eq: the deviator is scaled to it. An elastic step
  /// (dplastic 0) may return a lower bound of σy instead, never below eq.
  double yield = 0.0;
};

/// exp(s) for the small relative steps of Newton's method near its root: for |s| ≤ 2⁻¹⁰ the
/// series to s⁵ (its remainder below s⁶/720 < 2e-21), else std::exp.
inline double exp_of_step(double s) {
  if (!(std::abs(s) <= 0x1p-10)) return std::exp(s);
  return 1.0 + s * (1.0 + s * (0.5 + s * (1.0 / 6.0 + s * (1.0 / 24.0 + s * (1.0 / 120.0)))));
}

/// The start of the return: Newton's step in Δ from 0, Δ₀ = (eq − σy(0)) / (3G + σy'(0)),
/// inside the bracket and off the root only by the curvature of σy; the slope taken within
/// [0, 3G] (a softening slope, or Johnson–Cook's (ε̄p)ⁿ⁻¹ near ε̄p = 0, would start it far off).
inline double linearized_return(double eq, double g3, double y0, double dy0) {
  return (eq - y0) / (g3 + std::clamp(dy0, 0.0, g3));
}

/// Johnson–Cook's start: the return of the linearized law with its rate term,
///   eq − y0 − k Δ = a ln(Δ / Δr)   (a = y0 C, Δr = τ ε̇0, k = 3G + the hardening slope),
/// where the rate term bends the yield most. With x = k Δ / a it reads x + ln x = K,
/// K = (eq − y0)/a + ln(k Δr / a), solved by Newton's method in u = ln x (convex and
/// increasing: from the linearized return, to the right of the root, it falls monotonically)
/// to 1e-6 (the return's own Newton steps take it to round-off). Below Δr the rate factor is 1
/// and the linearized return stands.
inline double rate_return(double eq, double k, double y0, double a, double rate_strain) {
  const double d = (eq - y0) / k;
  if (!(a > 0.0) || !(d > rate_strain)) return d;
  const double kk = (eq - y0) / a + std::log(k * rate_strain / a);
  double u = std::log(k * d / a);
  for (int it = 0; it < 50; ++it) {
    const double e = std::exp(u), step = (e + u - kk) / (e + 1.0);
    u -= step;
    if (!(std::abs(step) > 1e-6)) break;
  }
  const double root = a * std::exp(u) / k;
  return root > 0.0 && root < d ? root : d;
}

/// The bracketed Newton solve of f(Δ) = eq − g3 Δ − σy(Δ) = 0 described above; yield(Δ, slope)
/// returns σy(Δ) and sets dσy/dΔ; it starts from d_start, in (0, eq/3G).
/// Newton in u = ln Δ: the relative step s = −f / (f'(Δ) Δ), Δ ← Δ eˢ. It stops
///  - when a step is at round-off (|s| ≤ 1e-13), taking it;
///  - when the quadratic convergence its steps show puts the next iterate at round-off: the
///    error after step k is about K s_k² with K ≈ |s_k| / s_{k−1}², so the step is taken and
///    the solve ends when |s_k|³ / s_{k−1}² ≤ 1e-14 (two Newton steps in a row, contracting);
///  - on a bracket narrowed to 1e-15 of itself, where bisection leads.
template <class Yield>
PlasticIncrement solve_return(double eq, double g3, double d_start, const Yield& yield) {
  PlasticIncrement r;
  double lo = 0.0, hi = eq / g3, dy = 0.0;
  double d = d_start;
  double last = 0.0;  // the previous relative Newton step (0: none, or a bisection)
  for (int it = 0; it < 100; ++it) {
    const double f = eq - g3 * d - yield(d, dy);
    if (f == 0.0) break;
    (f > 0.0 ? lo : hi) = d;
    const double slope = -g3 - dy;
    // Newton in ln Δ, where the rate term C ln(Δ/τ ε̇0) is linear (in Δ it bends so sharply
    // near 0 that Newton's steps overshoot the bracket and it crawls by bisection).
    if (slope < 0.0) {
      const double s = -f / (slope * d), next = d * exp_of_step(s);
      // At round-off the step may not move Δ off the bracket's end it just set: done.
      if (std::abs(s) <= 1e-13) {
        d = next;
        break;
      }
      if (next > lo && next < hi) {
        const double a = std::abs(s);
        const bool converged = a < std::abs(last) && a * a * a <= 1e-14 * last * last;
        d = next;
        last = s;
        if (converged) break;
        continue;
      }
    }
    const double next = lo > 0.0 ? std::sqrt(lo * hi) : 0.5 * (lo + hi);
    last = 0.0;
    const bool done = hi - lo <= 1e-15 * hi;
    d = next;
    if (done) break;
  }
  r.dplastic = d;
  r.yield = eq - g3 * d;  // on the yield surface, exactly as the return scales
  return r;
}

/// The return with the step's strength state ss (strength_state at the start of the step).
inline PlasticIncrement plastic_increment(const Material& m, const StrengthState& ss, double eq,
                                          double eps_p, double tau, double temperature,
                                          double rho) {
  PlasticIncrement r;
  eps_p += m.initial_plastic_strain;  // the hardening's strain: the cold work and the run's
  const double g = ss.g, g3 = 3.0 * g;
  if (m.strength == StrengthModel::bilinear) {
    r.yield = m.yield_stress + m.hardening_modulus * eps_p;
    if (eq > r.yield) {
      r.dplastic = (eq - r.yield) / (g3 + m.hardening_modulus);
      r.yield += m.hardening_modulus * r.dplastic;
    }
    return r;
  }
  const double heat = m.thermal() ? m.taylor_quinney / (rho * m.specific_heat) : 0.0;
  if (m.strength == StrengthModel::steinberg_guinan) {
    const SteinbergGuinan& sg = m.steinberg_guinan;
    if (g == 0.0) return r;  // molten (σy = 0): no deviator, no plastic strain to speak of
    // Elastic below a lower bound of σy(0) = Y(ε̄p) G(P, T)/G0 (G > 0 here, so the factor is
    // positive and T below melt): Y ≥ min(Y0, Ymax) while β, εi, n ≥ 0. The solver, and the
    // hardening's pow, only where the trial stress reaches it.
    const double cp = ss.pressure_factor;
    const double factor0 = cp - sg.b_temperature * (temperature - sg.reference_temperature);
    if (sg.beta >= 0.0 && sg.initial_strain >= 0.0 && sg.n >= 0.0) {
      r.yield = (sg.ymax > 0.0 ? std::min(sg.y0, sg.ymax) : sg.y0) * factor0;
      if (!(eq > r.yield)) return r;  // r.yield ≥ eq: a bound, not σy (nothing is scaled)
    }
    // σy(Δ) = Y(ε̄p + Δ) G(P, T(Δ)) / G0 with T(Δ) = T + heat (eq − 3G Δ) Δ.
    // The melt point T_m(η) (its exp and pow) only once the heated T reaches its lower bound.
    double tm = ss.melt;  // NaN: not computed, T below the bound
    const double tm_low = std::isnan(tm) ? steinberg_melt_lower_bound(sg, ss.eta) : tm;
    const auto molten = [&](double t) {
      if (std::isnan(tm)) {
        if (t < tm_low) return false;
        tm = steinberg_melt_temperature(sg, ss.eta);
      }
      return tm > 0.0 && t >= tm;
    };
    const auto yield = [&](double d, double& dy) {
      double dh = 0.0;
      const double y = steinberg_hardening(sg, eps_p + d, dh);
      const double t = temperature + heat * (eq - g3 * d) * d;
      double factor = cp - sg.b_temperature * (t - sg.reference_temperature);
      if (molten(t) || factor <= 0.0) {
        dy = 0.0;
        return 0.0;
      }
      dy = dh * factor - y * sg.b_temperature * heat * (eq - 2.0 * g3 * d);
      return y * factor;
    };
    double dy0 = 0.0;
    r.yield = yield(0.0, dy0);
    if (!(eq > r.yield)) return r;
    return solve_return(eq, g3, linearized_return(eq, g3, r.yield, dy0), yield);
  }
  const JohnsonCook& jc = m.johnson_cook;
  const bool softens = jc.melt_temperature > jc.room_temperature;
  // σy = S(ε̄p + Δ) R(Δ/τ) Θ(T(Δ)).
  const double span = jc.melt_temperature - jc.room_temperature;
  // Elastic below a lower bound of σy(0) = (A + B ε̄pⁿ) Θ(T) (R = 1 at Δ = 0) without its pows:
  // A Θ_low with Θ_low = 1 up to room temperature and 1 − T* for T* ≤ 1/2 and m ≥ 1 (T*ᵐ ≤ T*,
  // and Θ ≥ 1/2, so that round-off stays far below the 1e-9 taken off), none hotter; the
  // solver, and the pows, only where the trial stress reaches it (A, B ≥ 0, as every library
  // material has them).
  if (jc.a >= 0.0 && jc.b >= 0.0) {
    const double ts = softens ? (temperature - jc.room_temperature) / span : 0.0;
    const double theta = ts <= 0.0 ? 1.0 : (ts <= 0.5 && jc.m >= 1.0 ? 1.0 - ts : 0.0);
    r.yield = jc.a * theta * (1.0 - 1e-9);
    if (!(eq > r.yield)) return r;  // r.yield ≥ eq: a bound, not σy (nothing is scaled)
  }
  const auto yield = [&](double d, double& dy) {
    const double e = eps_p + d;
    const double pw = jc.b > 0.0 && e > 0.0 ? std::pow(e, jc.n) : 0.0;
    const double strain = jc.a + jc.b * pw;
    const double d_strain = jc.b > 0.0 && e > 0.0 ? jc.b * jc.n * pw / e : 0.0;
    const double star = d / (tau * jc.reference_rate);
    const double rate = star > 1.0 ? 1.0 + jc.c * std::log(star) : 1.0;
    const double d_rate = star > 1.0 ? jc.c / d : 0.0;
    double thermal = 1.0, d_thermal = 0.0;
    if (softens) {
      const double t = temperature + heat * (eq - g3 * d) * d;
      const double ts = (t - jc.room_temperature) / span;
      if (ts >= 1.0) {
        thermal = 0.0;
      } else if (ts > 0.0) {
        const double tm = std::pow(ts, jc.m);
        thermal = 1.0 - tm;
        d_thermal = -jc.m * tm / ts / span * heat * (eq - 2.0 * g3 * d);
      }
    }
    dy = d_strain * rate * thermal + strain * d_rate * thermal + strain * rate * d_thermal;
    return strain * rate * thermal;
  };
  double dy0 = 0.0;
  r.yield = yield(0.0, dy0);  // johnson_cook_yield(jc, ε̄p, 0, T), to the bit
  if (!(eq > r.yield)) return r;
  // f(eq/3G) = −σy at the start's temperature (no heating at the full return, σy's root): ≥ 0
  // only when molten, and then the deviator vanishes. Otherwise f(eq/3G) < 0 and, f(0) > 0,
  // the bracket holds the root.
  if (softens && temperature >= jc.melt_temperature) {
    r.dplastic = eq / g3;
    r.yield = 0.0;
    return r;
  }
  return solve_return(eq, g3,
                      rate_return(eq, g3 + std::clamp(dy0, 0.0, g3), r.yield, r.yield * jc.c,
                                  tau * jc.reference_rate),
                      yield);
}
/// The same from the pressure at the start of the step (Steinberg–Guinan's G(P, T)).
inline PlasticIncrement plastic_increment(const Material& m, double eq, double eps_p, double tau,
                                          double temperature, double rho, double pressure = 0.0) {
  const double eta = rho > 0.0 ? rho / m.density : 1.0;
  return plastic_increment(m, strength_state(m, pressure, temperature, eta), eq, eps_p, tau,
                           temperature, rho);
}

/// Result of the deviatoric update of one step.
struct DeviatorUpdate {
  Mat3 s;                 // deviatoric stress at the end of the step
  double dplastic = 0.0;  // Δε̄p, equivalent plastic strain increment
  double yield = 0.0;     // σy at the end of the step (0 for an elastic material; for an elastic
                       // step of Johnson–Cook or Steinberg–Guinan a lower bound of it, ≥ σ_eq)
};

/// Hypoelastic-plastic deviator, one step:
///   trial  s* = Q s Qᵀ + 2G τ dev D                      (Jaumann rate, Hughes–Winget)
///   σ_eq = sqrt(3/2 s*:s*),  σy = σy0 + H ε̄p
///   if σ_eq > σy:  Δε̄p = (σ_eq − σy) / (3G + H),  s = s* (σy + H Δε̄p) / σ_eq   (radial return)
/// (the other laws: plastic_increment). The returned stress lies on the updated yield surface
/// exactly (to round-off). G is G0, or Steinberg–Guinan's G(P, T) at the start of the step.
inline DeviatorUpdate update_deviator(const Material& m, const Mat3& s_old, const Mat3& D,
                                      const Mat3& W, double tau, double eps_p,
                                      double temperature = 0.0, double rho = 0.0,
                                      double pressure = 0.0) {
  const Mat3 Q = jaumann_rotation(W, tau);
  const Mat3 devD = D - (D.trace() / 3.0) * Mat3::Identity();
  const StrengthState ss =
      strength_state(m, pressure, temperature, rho > 0.0 ? rho / m.density : 1.0);
  DeviatorUpdate r;
  r.s = Q * s_old * Q.transpose() + (2.0 * ss.g * tau) * devD;
  if (!m.plastic()) return r;
  const double eq = std::sqrt(1.5 * r.s.cwiseProduct(r.s).sum());
  const PlasticIncrement inc = plastic_increment(m, ss, eq, eps_p, tau, temperature, rho);
  r.yield = inc.yield;
  r.dplastic = inc.dplastic;
  if (inc.yield < eq) r.s *= inc.yield / eq;
  return r;
}

/// The same update on the symmetric storage the kernel keeps (the fast path; tests hold it to
/// update_deviator). d: the strain rate D as (xx, yy, zz, xy, yz, xz); w: the spin's axial
/// vector (W v = w × v). Updates s in place and returns Δε̄p and the end-of-step yield.
struct DeviatorIncrement {
  double dplastic = 0.0;
  double yield = 0.0;
};
/// Its rotation and elastic trial, s* = Q s Qᵀ + g2 dev D with g2 = 2 G τ, on values (the
/// element stage's SIMD lanes call it lane by lane: the same operations, element.cpp).
[[gnu::always_inline]] inline Sym6 jaumann_trial(const Sym6& s, const Sym6& d,
                                                 const std::array<double, 3>& w, double tau,
                                                 double g2) {
  // Q = (1 − c θ²) I + c A + c α αᵀ with α = τ w / 2, θ² = |α|², c = 2 / (1 + θ²).
  const double ax = 0.5 * tau * w[0], ay = 0.5 * tau * w[1], az = 0.5 * tau * w[2];
  const double th2 = ax * ax + ay * ay + az * az, c = 2.0 / (1.0 + th2), dg = 1.0 - c * th2;
  const double q00 = dg + c * ax * ax, q11 = dg + c * ay * ay, q22 = dg + c * az * az;
  const double q01 = c * (ax * ay - az), q10 = c * (ax * ay + az);
  const double q02 = c * (ax * az + ay), q20 = c * (ax * az - ay);
  const double q12 = c * (ay * az - ax), q21 = c * (ay * az + ax);
  // M = Q s, then s' = M Qᵀ (symmetric: six entries).
  const double s00 = s[0], s11 = s[1], s22 = s[2], s01 = s[3], s12 = s[4], s02 = s[5];
  const double m00 = q00 * s00 + q01 * s01 + q02 * s02, m01 = q00 * s01 + q01 * s11 + q02 * s12,
               m02 = q00 * s02 + q01 * s12 + q02 * s22;
  const double m10 = q10 * s00 + q11 * s01 + q12 * s02, m11 = q10 * s01 + q11 * s11 + q12 * s12,
               m12 = q10 * s02 + q11 * s12 + q12 * s22;
  const double m20 = q20 * s00 + q21 * s01 + q22 * s02, m21 = q20 * s01 + q21 * s11 + q22 * s12,
               m22 = q20 * s02 + q21 * s12 + q22 * s22;
  const double tr3 = (d[0] + d[1] + d[2]) / 3.0;
  return Sym6{m00 * q00 + m01 * q01 + m02 * q02 + g2 * (d[0] - tr3),
              m10 * q10 + m11 * q11 + m12 * q12 + g2 * (d[1] - tr3),
              m20 * q20 + m21 * q21 + m22 * q22 + g2 * (d[2] - tr3),
              m00 * q10 + m01 * q11 + m02 * q12 + g2 * d[3],
              m10 * q20 + m11 * q21 + m12 * q22 + g2 * d[4],
              m00 * q20 + m01 * q21 + m02 * q22 + g2 * d[5]};
}
inline DeviatorIncrement update_deviator6(const Material& m, Sym6& s, const Sym6& d,
                                          const std::array<double, 3>& w, double tau, double eps_p,
                                          double temperature = 0.0, double rho = 0.0,
                                          double pressure = 0.0) {
  const StrengthState ss =
      strength_state(m, pressure, temperature, rho > 0.0 ? rho / m.density : 1.0);
  s = jaumann_trial(s, d, w, tau, 2.0 * ss.g * tau);
  DeviatorIncrement r;
  if (!m.plastic()) return r;
  const double s2 =
      s[0] * s[0] + s[1] * s[1] + s[2] * s[2] + 2.0 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5]);
  const double eq = std::sqrt(1.5 * s2);
  const PlasticIncrement inc = plastic_increment(m, ss, eq, eps_p, tau, temperature, rho);
  r.yield = inc.yield;
  r.dplastic = inc.dplastic;
  if (inc.yield < eq) {
    const double f = inc.yield / eq;
    for (double& v : s) v *= f;
  }
  return r;
}

/// The equation of state as p = A(μ) + B E, with μ = V0/V − 1 (compression > 0) and E the
/// internal energy per unit reference volume (J/m³). Linear: A = K μ, B = 0.
/// Mie–Grüneisen with a linear Us–up Hugoniot (the form of LS-DYNA's *EOS_GRUNEISEN with
/// S2 = S3 = a = 0):
///   μ > 0:  A = ρ0 c0² μ [1 + (1 − Γ0/2) μ] / [1 − (s − 1) μ]²
///   μ ≤ 0:  A = ρ0 c0² μ
///   B = Γ0
/// On the Hugoniot (E = E_H = ½ p_H μ/(1+μ)) this gives p_H = ρ0 Us up with Us = c0 + s up.
/// Tillotson's pressure is not linear in E: its terms are its tangent at the given E,
/// B = ∂p/∂E and A = p − B E, so that A + B E is the pressure there.
struct EosTerms {
  double a = 0.0;       // A: A(μ), Pa (Tillotson's: p − B E at the state)
  double b = 0.0;       // B = ∂p/∂E
  double da_dmu = 0.0;  // ∂p/∂μ at constant E, for the sound speed
};

/// Tillotson's pressure and its partial derivatives at compression μ and energy per reference
/// volume E (ρ e = η E, ∂ω/∂η = −2 (ω − 1)/η, ∂(η E/ω)/∂E = η/ω²).
inline EosTerms tillotson_terms(const Tillotson& t, double density, double mu, double energy) {
  const double eta = 1.0 + mu;
  const double rho_e = eta * energy;
  const double specific = energy / density;
  const double omega = 1.0 + std::max(specific, 0.0) / (t.e0 * eta * eta);
  const double dw_de = specific > 0.0 ? 1.0 / (density * t.e0 * eta * eta) : 0.0;  // ∂ω/∂E
  const double dw_deta = -2.0 * (omega - 1.0) / eta;                               // ∂ω/∂η
  // ∂(η E/ω)/∂E and ∂(η E/ω)/∂η
  const double g_e = eta / omega - rho_e * dw_de / (omega * omega);
  const double g_eta = energy / omega - rho_e * dw_deta / (omega * omega);
  // The compressed (and cold) branch.
  const double pc = (t.a + t.b / omega) * rho_e + t.big_a * mu + t.big_b * mu * mu;
  const double pc_e = t.a * eta + t.b * g_e;
  const double pc_eta = t.a * energy + t.b * g_eta + t.big_a + 2.0 * t.big_b * mu;
  EosTerms r;
  double p = pc, p_e = pc_e, p_eta = pc_eta;
  if (mu < 0.0 && specific > t.e_iv) {
    const double z = 1.0 / eta - 1.0, dz = -1.0 / (eta * eta);
    const double fa = std::exp(-t.alpha * z * z), fb = std::exp(-t.beta * z);
    const double inner = t.b * rho_e / omega + t.big_a * mu * fb;
    const double pe = t.a * rho_e + inner * fa;
    const double pe_e = t.a * eta + t.b * g_e * fa;
    const double pe_eta = t.a * energy +
                          (t.b * g_eta + t.big_a * fb * (1.0 - t.beta * mu * dz)) * fa -
                          inner * fa * 2.0 * t.alpha * z * dz;
    if (specific >= t.e_cv) {
      p = pe, p_e = pe_e, p_eta = pe_eta;
    } else {
      const double span = t.e_cv - t.e_iv, w = (specific - t.e_iv) / span;
      p = w * pe + (1.0 - w) * pc;
      p_e = w * pe_e + (1.0 - w) * pc_e + (pe - pc) / (density * span);
      p_eta = w * pe_eta + (1.0 - w) * pc_eta;
    }
  }
  r.b = p_e;
  r.a = p - p_e * energy;
  r.da_dmu = p_eta;
  return r;
}

/// The EOS's terms at compression μ and energy per reference volume E (E enters Tillotson's
/// alone).
inline EosTerms eos_terms(const Material& m, double mu, double energy = 0.0) {
  EosTerms t;
  if (m.eos == EosKind::linear) {
    t.a = m.bulk_modulus * mu;
    t.da_dmu = m.bulk_modulus;
    return t;
  }
  if (m.eos == EosKind::tillotson) return tillotson_terms(m.tillotson, m.density, mu, energy);
  const double k0 = m.density * m.c0 * m.c0;
  t.b = m.gamma0;
  if (mu <= 0.0) {
    t.a = k0 * mu;
    t.da_dmu = k0;
    return t;
  }
  const double num = mu * (1.0 + (1.0 - 0.5 * m.gamma0) * mu);
  const double den = 1.0 - (m.s - 1.0) * mu;
  t.a = k0 * num / (den * den);
  const double dnum = 1.0 + 2.0 * (1.0 - 0.5 * m.gamma0) * mu;
  t.da_dmu = k0 * (dnum * den + 2.0 * (m.s - 1.0) * num) / (den * den * den);
  return t;
}

/// Pressure from compression μ and internal energy per reference volume E.
inline double eos_pressure(const Material& m, double mu, double energy_density) {
  const EosTerms t = eos_terms(m, mu, energy_density);
  return t.a + t.b * energy_density;
}

/// Isentropic bulk stiffness ρ c_b² = (1+μ) dp/dμ|_s, with dE/dμ|_s = p/(1+μ)²:
///   ρ c_b² = (1+μ) A'(μ) + B p / (1+μ).
/// Floored at 1e-3 K0 so that a material in tension keeps a usable sound speed.
inline double bulk_stiffness(const Material& m, double mu, double p, const EosTerms& t) {
  const double k = (1.0 + mu) * t.da_dmu + t.b * p / (1.0 + mu);
  return std::max(k, 1e-3 * m.bulk_modulus);
}
inline double bulk_stiffness(const Material& m, double mu, double p, double energy = 0.0) {
  return bulk_stiffness(m, mu, p, eos_terms(m, mu, energy));
}

/// Artificial bulk viscosity (von Neumann–Richtmyer quadratic + Landshoff linear), on
/// compression only:
///   q = ρ l (C2 l ε̇v² − C1 c ε̇v)  for ε̇v = tr D < 0,   q = 0 otherwise,
/// with l the element's characteristic length (smallest altitude) and c its sound speed.
inline double bulk_viscosity(double rho, double length, double sound_speed, double trace_d,
                             double c_linear, double c_quadratic) {
  if (trace_d >= 0.0) return 0.0;  // expansion: no viscosity
  return rho * length *
         (c_quadratic * length * trace_d * trace_d - c_linear * sound_speed * trace_d);
}

}  // namespace tc
