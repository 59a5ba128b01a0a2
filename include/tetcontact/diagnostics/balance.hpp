// Conservation measures: energy and momentum at a time level, and per-body statistics.
#pragma once

#include <string>
#include <vector>

#include "tetcontact/solver/model.hpp"
#include "tetcontact/solver/state.hpp"

namespace tc {

/// Work and impulse of one kind of external impulse (prescribed velocities, walls),
/// accumulated between samples in the leapfrog's bookkeeping (see sample_balance).
struct ImpulseLedger {
  double work = 0.0;            // to t^n, J
  Vec3 impulse = Vec3::Zero();  // to t^n, N s
  double power_ahead = 0.0;     // Σ J^n·U^{n+1} (half of the next interval's work)
  Vec3 now = Vec3::Zero();      // Σ J^n
};

/// Balance at t^n, sampled after the prediction (and corrections) of step n, when both U^n
/// and U^{n+1} are known.
struct Sample {
  long step = 0;
  double t = 0.0;
  double dt = 0.0;
  double kinetic = 0.0;        // ½ Σ m U^n·(U^n + τ^{n-1/2} a^n)  (see below)
  double internal = 0.0;       // Σ e_int over tets: elastic + plastic work + viscous heat
  double plastic_work = 0.0;   // part of internal
  double viscous_work = 0.0;   // part of internal
  ImpulseLedger boundary;      // prescribed velocities: work and impulse to t^n
  ImpulseLedger walls;         // rigid walls: work and impulse to t^n
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
/// it is ½ m |U^0|². The work of external impulses J (prescribed velocities, walls) between
/// two samples is ½ U^{n+1}·(J^n + J^{n+1}) in the same bookkeeping, and the centred
/// momentum moves by ½ (J^n + J^{n+1}); so `previous` must be the sample of the step before
/// (nullptr for the first).
Sample sample_balance(const State& st, const Sample* previous);

/// Velocity at t^n: (U^n + U^{n+1}) / 2.
inline Vec3 centred_velocity(const State& st, Index node) {
  return 0.5 * (st.v[node] + st.v_star[node]);
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
