// The material update of one material point over a step: a tet of the element stage, or an SPH
// particle (sph/). Both hand it the point's motion (its rate of deformation, spin and volumes
// at mid-step and at the end) and its state by reference; the laws it calls are those of
// material/material.hpp, so a tet and a particle of one material obey the very same
// deviator, strength, equation of state, temperature and failure.
#pragma once

#include <Eigen/Eigenvalues>
#include <array>
#include <cmath>

#include "tetcontact/material/material.hpp"
#include "tetcontact/model/state.hpp"

namespace tc {

/// One point's state, by reference into its arrays (State's per-tet arrays, or
/// ParticleMatter's per-particle ones).
struct MaterialPoint {
  Sym6& s;                // deviatoric stress
  double& p;              // pressure (compression > 0)
  double& q;              // artificial bulk viscosity, a pressure
  double& e_int;          // internal energy, J
  double& eps_p;          // equivalent plastic strain
  double& ductile;        // Johnson–Cook's damage D
  double& ductile_floor;  // the part of D accrued with ε_f at its floor
  double& w_plastic;      // plastic work, J
  double& w_viscous;      // viscous (shock) heat, J
  double& sound2;         // dilatational sound speed squared
  double& trace_d;        // tr D of the step
  double& temperature;    // K
  double& vol;            // current volume (Vⁿ before the step, Vⁿ⁺¹ after)
  double vol0;            // reference volume
  Damage& damage;
};

inline MaterialPoint tet_point(State& st, Index t) {
  return {st.s[t],
          st.p[t],
          st.q[t],
          st.e_int[t],
          st.eps_p[t],
          st.ductile[t],
          st.ductile_floor[t],
          st.w_plastic[t],
          st.w_viscous[t],
          st.sound2[t],
          st.trace_d[t],
          st.temperature[t],
          st.vol[t],
          st.vol0[t],
          st.damage[t]};
}

/// A point's motion over the step τ: the rate of deformation D (xx, yy, zz, xy, yz, xz), the
/// spin's axial vector w (W v = w × v), tr D, and its volume at mid-step and at the end.
struct PointMotion {
  Sym6 d;
  std::array<double, 3> w;
  double trace = 0.0;
  double vol_mid = 0.0, vol_end = 0.0;
};

/// The rates of a velocity gradient L (L[a][b] = ∂v^a/∂x^b): D = ½ (L + Lᵀ), the spin
/// W = ½ (L − Lᵀ) as its axial vector, and tr D (the volumes are the caller's).
inline void set_rates(const double (&L)[3][3], PointMotion& c) {
  c.d = Sym6{L[0][0],
             L[1][1],
             L[2][2],
             0.5 * (L[0][1] + L[1][0]),
             0.5 * (L[1][2] + L[2][1]),
             0.5 * (L[0][2] + L[2][0])};
  c.w = {0.5 * (L[2][1] - L[1][2]), 0.5 * (L[0][2] - L[2][0]), 0.5 * (L[1][0] - L[0][1])};
  c.trace = c.d[0] + c.d[1] + c.d[2];
}

/// Dobritsa et al.'s spall criterion: the largest principal stress σ1 = λmax(s) − p exceeds σ*.
/// For a deviator λmax(s) ≤ √(2/3) |s|, which clears most points without an eigenvalue solve.
inline bool spalls(const Material& m, const Sym6& s, double p) {
  if (!(m.spall_strength > 0.0)) return false;
  const double n2 =
      s[0] * s[0] + s[1] * s[1] + s[2] * s[2] + 2.0 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5]);
  if (std::sqrt(2.0 / 3.0 * n2) * (1.0 + 1e-9) - p <= m.spall_strength) return false;
  Eigen::SelfAdjointEigenSolver<Mat3> es;
  es.computeDirect(to_mat3(s), Eigen::EigenvaluesOnly);
  return es.eigenvalues().maxCoeff() - p > m.spall_strength;
}

/// Failure at the end of the step (Dobritsa et al.): an intact point that spalls is damaged, its
/// deviator dropped; a damaged point loosened past χ = 1 − V0/V > χ* is destroyed. Returns the
/// pressure the point may carry: none in tension once damaged; a destroyed one none while it
/// is loosened (χ > 0), and its EOS pressure again only once pressed back below its reference
/// volume (μ > 0): with no pressure at all, destroyed cells that neighbours compress again
/// collapse, and the spall plate's step fell to 3e-14 s.
inline double fail(const Material& m, double vol, double p, MaterialPoint pt) {
  Damage& dmg = pt.damage;
  if (dmg == Damage::intact && spalls(m, pt.s, p)) {
    dmg = Damage::damaged;
    pt.s = Sym6{0, 0, 0, 0, 0, 0};
  }
  const double chi = 1.0 - pt.vol0 / vol;
  if (dmg == Damage::damaged && chi > m.loosening_limit) dmg = Damage::destroyed;
  if (dmg == Damage::intact) return p;
  if (p < 0.0 || (dmg == Damage::destroyed && chi > 0.0)) return 0.0;
  return p;
}

/// The energy at the end of the step with the EOS pressure it implies:
///   E^{n+1} = E + W − ½ (pⁿ + p^{n+1}) ΔV,  p^{n+1} = A(μ) + B E^{n+1}/V0,
/// solved for E^{n+1}; `e` holds Eⁿ and the work done before the pressure's, `w` the rest.
inline double implicit_energy(double e, double w, double p_old, const EosTerms& eos, double dvol,
                              double vol0) {
  return (e - 0.5 * (p_old + eos.a) * dvol + w) / (1.0 + 0.5 * eos.b * dvol / vol0);
}

/// The end of the step's energy, pressure and EOS terms at compression μ: implicit_energy with
/// the EOS's terms. An EOS linear in E (linear, Mie–Grüneisen) is solved at once; Tillotson's
/// by Newton's iteration, its tangent taken at the explicit estimate E + W − pⁿ ΔV and then at
/// each new E^{n+1}: three solves (on the material tests' hot expansion the pressure returned
/// is off the EOS by 9e-6 after one, 2e-14 after two). Each solve keeps
/// E^{n+1} = E + W − ½ (pⁿ + p^{n+1}) ΔV with the p^{n+1} it returns, so the energy balance
/// holds whatever the iteration left of the EOS's own pressure.
struct EnergySolve {
  double e = 0.0, p = 0.0;
  EosTerms eos;
};
inline EnergySolve solve_energy(const Material& m, double mu, double e, double w, double p_old,
                                double dvol, double vol0) {
  EnergySolve r;
  const int passes = m.eos == EosKind::tillotson ? 3 : 1;
  double guess = e + w - p_old * dvol;
  for (int k = 0; k < passes; ++k) {
    r.eos = eos_terms(m, mu, guess / vol0);
    r.e = implicit_energy(e, w, p_old, r.eos, dvol, vol0);
    guess = r.e;
  }
  r.p = r.eos.a + r.eos.b * r.e / vol0;
  return r;
}

/// Squared dilatational sound speed of the current state: (ρ c_b² + 4G/3) / ρ, with G at the
/// state (Steinberg–Guinan's G(P, T) rises with pressure).
inline double sound_speed2(const Material& m, double mu, double p, const EosTerms& t,
                           double temperature) {
  const double rho = m.density * (1.0 + mu);
  const double g = shear_modulus_at(m, p, temperature, 1.0 + mu);
  return (bulk_stiffness(m, mu, p, t) + 4.0 / 3.0 * g) / rho;
}

/// A plastic step's failure, after its plastic strain Δε̄p > 0 is in pt.eps_p and its returned
/// deviator in pt.s (pt.p and pt.temperature still the start's): true when the point reaches the
/// strain limit or Johnson–Cook's ductile damage D = 1,
///   D += Δε̄p / ε_f(σ*, ε̇p, T),  σ* = −p / σ_eq,
/// the increments taken with ε_f at its floor also summed apart (`ductile_floor`), or left out
/// where the material has no ductile failure at the floor.
inline bool plastic_failure(const Material& mat, double dplastic, double tau, MaterialPoint pt) {
  bool eroding = mat.erosion_plastic_strain > 0.0 && pt.eps_p >= mat.erosion_plastic_strain;
  if (mat.ductile_failure) {
    const double eq = von_mises(pt.s);
    const double triax = eq > 0.0 ? -pt.p / eq : 0.0;
    const double ef = johnson_cook_failure_strain(mat.johnson_cook_failure, triax, dplastic / tau,
                                                  pt.temperature);
    const bool floored = ef <= mat.johnson_cook_failure.min_strain;
    if (!floored || mat.ductile_failure_at_floor) {
      pt.ductile += dplastic / ef;
      if (floored) pt.ductile_floor += dplastic / ef;
    }
    if (pt.ductile >= 1.0) eroding = true;
  }
  return eroding;
}

/// The deviator (Jaumann rate, radial return; none in a failed point) and its trapezoidal work
/// τ V ½(sⁿ + sⁿ⁺¹) : D at mid-step volume V, returned; the plastic work V σy Δε̄p into `w_p`
/// (bilinear with σy at mid-increment, exact for linear hardening; the other laws at the end of
/// the step, the heating their return assumed), the plastic strain, and `eroding` set when the
/// point reaches the strain limit or Johnson–Cook's ductile damage D = 1:
///   D += Δε̄p / ε_f(σ*, ε̇p, T),  σ* = −p / σ_eq  (the start's pressure, the returned deviator);
/// the increments taken with ε_f at its floor are also summed apart (`ductile_floor`), or left
/// out where the material has no ductile failure at the floor. `failed`: the point is damaged
/// and the case has fracture (no deviator). `d_work`: the rate the work is taken with, the
/// forces' own where the stress is updated with a corrected one (an SPH particle at a face);
/// c.d otherwise.
[[gnu::always_inline]] inline double deviator_work(const Material& mat, const PointMotion& c,
                                                   const Sym6& d_work, double rho_mid, bool failed,
                                                   double tau, MaterialPoint pt, double& w_p,
                                                   bool& eroding) {
  const Sym6 s_old = pt.s;
  const DeviatorIncrement inc =
      failed ? DeviatorIncrement{}
             : update_deviator6(mat, pt.s, c.d, c.w, tau, pt.eps_p, pt.temperature, rho_mid, pt.p);
  const Sym6& s_new = pt.s;
  double sd = 0.0;
  for (int k = 0; k < 6; ++k) sd += (k < 3 ? 1.0 : 2.0) * (s_old[k] + s_new[k]) * d_work[k];
  const double w_dev = 0.5 * tau * c.vol_mid * sd;
  w_p = 0.0;
  if (inc.dplastic > 0.0) {
    const double y = mat.strength == StrengthModel::bilinear
                         ? inc.yield - 0.5 * mat.hardening_modulus * inc.dplastic
                         : inc.yield;
    w_p = c.vol_mid * y * inc.dplastic;
    pt.w_plastic += w_p;
    pt.eps_p += inc.dplastic;
    if (plastic_failure(mat, inc.dplastic, tau, pt)) eroding = true;
  }
  return w_dev;
}

/// The viscosity q the point carries at the end of the step (its geometry's own: a tet's
/// bulk_viscosity, 0 for a particle, whose viscosity acts between pairs) and its work,
/// returned, the trapezoid of the values at both ends of the step (q^{n+1/2} is what the forces
/// at t^{n+1} carry), as for the pressure. The point takes its end volume (`dvol` the change)
/// and the heat: the viscous (shock) heat and the fraction χ of the plastic work.
[[gnu::always_inline]] inline double viscous_work(const Material& mat, const PointMotion& c,
                                                  double q, double w_p, MaterialPoint pt,
                                                  double& dvol) {
  dvol = c.vol_end - pt.vol;
  const double w_q = -0.5 * (pt.q + q) * dvol;
  pt.q = q;
  pt.trace_d = c.trace;
  pt.w_viscous += w_q;
  pt.vol = c.vol_end;
  if (mat.thermal())
    pt.temperature +=
        (mat.taylor_quinney * w_p + w_q) / (mat.density * pt.vol0 * mat.specific_heat);
  return w_q;
}

/// The point's own pressure, p^{n+1} = A(μ) + B E^{n+1}/V0 with
///   E^{n+1} = E^n + W_dev − ½ (p^n + p^{n+1}) ΔV + W_q, solved for E^{n+1} (solve_energy),
/// failure (with `fracture`: the pressure a failed point carries, its energy with it), and the
/// sound speed. After viscous_work (the point at its end volume).
[[gnu::always_inline]] inline void point_pressure(const Material& mat, double w_dev, double w_q,
                                                  double dvol, bool fracture, MaterialPoint pt) {
  const double mu = pt.vol0 / pt.vol - 1.0;
  const EnergySolve solved = solve_energy(mat, mu, pt.e_int + w_dev, w_q, pt.p, dvol, pt.vol0);
  const EosTerms& eos = solved.eos;
  double e_new = solved.e;
  double p_new = solved.p;
  if (fracture) {
    const double carried = fail(mat, pt.vol, p_new, pt);
    if (carried != p_new) {
      p_new = carried;
      e_new = pt.e_int + w_dev - 0.5 * (pt.p + p_new) * dvol + w_q;
    }
  }
  pt.e_int = e_new;
  pt.p = p_new;
  pt.sound2 = sound_speed2(mat, mu, pt.p, eos, pt.temperature);
}

}  // namespace tc
