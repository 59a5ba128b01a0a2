// Conservation measures: energy and momentum at a time level, and per-body statistics.
#pragma once

#include <algorithm>

#include <string>
#include <vector>

#include "tetcontact/solver/model.hpp"
#include "tetcontact/solver/state.hpp"

namespace tc {

/// Work and impulse of one kind of external impulse (prescribed velocities, walls),
/// accumulated between samples in the leapfrog's bookkeeping (see sample_balance).
struct ImpulseLedger {
  double work = 0.0;                  // to t^n, J
  Vec3 impulse = Vec3::Zero();        // to t^n, N s
  double work_ahead = 0.0;            // the share of this step's impulses due at t^{n+1}
  Vec3 impulse_ahead = Vec3::Zero();  // likewise for the impulse
};

/// Balance at t^n, sampled after the prediction (and corrections) of step n, when both U^n
/// and U^{n+1} are known.
struct Sample {
  long step = 0;
  double t = 0.0;
  double dt = 0.0;
  double kinetic = 0.0;        // ½ Σ m U^n·(U^n + τ^{n-1/2} a^n)  (see below)
  double internal = 0.0;       // Σ e_int over tets (elastic + plastic work + viscous heat)
                               // and the energy particles carry
  double plastic_work = 0.0;   // part of internal
  double viscous_work = 0.0;   // part of internal
  ImpulseLedger boundary;      // prescribed velocities: work and impulse to t^n
  ImpulseLedger walls;         // rigid walls: work and impulse to t^n
  ImpulseLedger contact;       // contacts between bodies: work (≤ 0) and impulse (≈ 0) to t^n
  double contact_force = 0.0;  // total normal contact force this step (Σ λ / τ), N
  long contacts = 0;           // node–face contacts this step
  long damaged = 0;            // cells spalled (damaged, not destroyed) at t^n
  long destroyed = 0;          // cells destroyed (loosened) at t^n
  long particles = 0;          // cells turned into particles so far
  double particle_mass = 0.0;  // kg carried by particles (part of mass)
  double total = 0.0;          // kinetic + internal
  double balance_error = 0.0;  // filled by the Simulation (see balance_error_max)
  double mass = 0.0;
  Vec3 momentum = Vec3::Zero();    // Σ m (U^n + U^{n+1}) / 2
  double momentum_scale = 0.0;     // Σ m |U^n + U^{n+1}| / 2, for relative errors
  std::vector<double> wall_force;  // normal reaction force on each wall this step, N

  /// Work done on the bodies by everything outside them (boundary conditions, walls).
  double external_work() const { return boundary.work + walls.work; }
  Vec3 external_impulse() const { return boundary.impulse + walls.impulse; }
};

/// Kinetic energy at t^n is the product ½ Σ m U^{n-1/2}·(U^{n-1/2} + τ^{n-1/2} a^n), where
/// U = U^{n-1/2} is the last committed velocity and a^n the acceleration of this step's
/// prediction. With a constant step it is the leapfrog's time-centred ½ m U^{n-1/2}·U^{n+1/2},
/// and with the trapezoidal internal energy kinetic + internal is then conserved exactly by
/// the central difference for small-strain linear elasticity. When the step changes by Δτ
/// the mismatch is O((ωτ)² Δτ/τ) of the energy (the plain ½ m|U|² of a half-step velocity
/// errs by O(ωτ), ½ m U^{n-1/2}·U^{n+1/2} by O(ωτ Δτ/τ)). On the first step (τ^{-1/2} = 0)
/// it is ½ m |U^0|². Velocities at t^n are v^n = U^n + f (U* − U^n), f = τ^{n-1/2}/(2τ_v)
/// (½ for a constant step, 0 on the first: v^0 = U^0), and momentum is Σ m v^n. An external
/// impulse J^n (prescribed velocities, walls) does the work J^n·(U^n + U^{n+1})/2; in this
/// bookkeeping the share f J^n·U^n falls at t^n and the rest at t^{n+1}, and its momentum
/// f J^n at t^n and (1 − f) J^n at t^{n+1}. So `previous` must be the sample of the step
/// before (nullptr for the first).
Sample sample_balance(const State& st, const Sample* previous);

/// Momentum balance over a run, relative: |P_last − P_first − external impulse| over the larger
/// momentum scale (0 when nothing moves).
inline double momentum_error(const Sample& first, const Sample& last) {
  const double scale = std::max(first.momentum_scale, last.momentum_scale);
  return scale > 0 ? (last.momentum - first.momentum - last.external_impulse()).norm() / scale
                   : 0.0;
}

/// f = τ^{n-1/2} / (2 τ_v): how far the velocity at t^n lies from U^n towards U*.
inline double kick_fraction(const State& st) {
  const double tau_v = 0.5 * (st.dt_prev + st.dt);
  return tau_v > 0.0 ? 0.5 * st.dt_prev / tau_v : 0.0;
}

/// Velocity at t^n: U^n + f (U* − U^n) ((U^n + U^{n+1})/2 for a constant step; U^0 at t = 0).
inline Vec3 centred_velocity(const State& st, Index node) {
  return st.v[node] + kick_fraction(st) * (st.v_star[node] - st.v[node]);
}

struct BodyStats {
  std::string name;
  double mass = 0.0;
  Vec3 velocity = Vec3::Zero();  // mass-averaged, time-centred
  Vec3 bbox_min = Vec3::Zero();
  Vec3 bbox_max = Vec3::Zero();
};

std::vector<BodyStats> body_stats(const Model& model, const State& st);

}  // namespace tc
