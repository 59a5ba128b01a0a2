// Conservation measures: energy and momentum at a time level, and per-body statistics.
#pragma once

#include <algorithm>

#include <string>
#include <vector>

#include "tetcontact/model/model.hpp"
#include "tetcontact/model/sample.hpp"
#include "tetcontact/model/state.hpp"
#include "tetcontact/parallel/exact_sum.hpp"

namespace tc {

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
/// The sums over tets the balance reads, exact (parallel/exact_sum.hpp): the same bits for any
/// order of the tets, so a distributed run adds its own and merges the ranks' partials.
struct TetSums {
  ExactSum internal, plastic_work, viscous_work;
};
/// Over `tets` (all the tets when null).
TetSums tet_sums(const State& st, const std::vector<Index>* tets = nullptr);

/// `sums`: the tets' sums when the caller made them (a distributed run); else made here.
Sample sample_balance(const State& st, const Sample* previous, const TetSums* sums = nullptr);

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
