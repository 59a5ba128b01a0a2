#include "tetcontact/diagnostics/balance.hpp"

namespace tc {

namespace {

void account(const std::vector<Vec3>& impulse, const State& st, const ImpulseLedger* previous,
             ImpulseLedger& out) {
  double power_behind = 0.0;  // Σ J^n·U^n
  for (std::size_t i = 0; i < impulse.size(); ++i) {
    power_behind += impulse[i].dot(st.v[i]);
    out.power_ahead += impulse[i].dot(st.v_star[i]);
    out.now += impulse[i];
  }
  if (previous) {
    out.work = previous->work + 0.5 * (previous->power_ahead + power_behind);
    out.impulse = previous->impulse + 0.5 * (previous->now + out.now);
  }
}

}  // namespace

Sample sample_balance(const State& st, const Sample* previous) {
  Sample s;
  s.step = st.step;
  s.t = st.t;
  s.dt = st.dt;
  // U* − U^n = τ_v a^n (external impulses included); the left step τ^{n-1/2} scales it.
  const double tau_v = 0.5 * (st.dt_prev + st.dt);
  const double w = tau_v > 0.0 ? st.dt_prev / tau_v : 0.0;
  for (std::size_t i = 0; i < st.x.size(); ++i) {
    s.kinetic += 0.5 * st.m[i] * st.v[i].dot(st.v[i] + w * (st.v_star[i] - st.v[i]));
    s.mass += st.m[i];
    const Vec3 p = 0.5 * st.m[i] * (st.v[i] + st.v_star[i]);
    s.momentum += p;
    s.momentum_scale += p.norm();
  }
  for (std::size_t t = 0; t < st.e_int.size(); ++t) {
    s.internal += st.e_int[t];
    s.plastic_work += st.w_plastic[t];
    s.viscous_work += st.w_viscous[t];
  }
  account(st.bc_impulse, st, previous ? &previous->boundary : nullptr, s.boundary);
  account(st.wall_impulse, st, previous ? &previous->walls : nullptr, s.walls);
  s.total = s.kinetic + s.internal;
  return s;
}

std::vector<BodyStats> body_stats(const Model& model, const State& st) {
  std::vector<BodyStats> out;
  for (const BodyRange& b : model.mesh.bodies) {
    BodyStats s;
    s.name = b.name;
    s.bbox_min = st.x[b.node_begin];
    s.bbox_max = st.x[b.node_begin];
    Vec3 p = Vec3::Zero();
    for (Index i = b.node_begin; i < b.node_end; ++i) {
      s.mass += st.m[i];
      p += st.m[i] * centred_velocity(st, i);
      s.bbox_min = s.bbox_min.cwiseMin(st.x[i]);
      s.bbox_max = s.bbox_max.cwiseMax(st.x[i]);
    }
    s.velocity = p / s.mass;
    out.push_back(s);
  }
  return out;
}

}  // namespace tc
