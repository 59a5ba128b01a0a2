#include "tetcontact/diagnostics/balance.hpp"

namespace tc {

Sample sample_balance(const State& st, const Sample* previous) {
  Sample s;
  s.step = st.step;
  s.t = st.t;
  s.dt = st.dt;
  double power_behind = 0.0;  // Σ J^n·U^n
  // U* − U^n = τ_v a^n (prescribed impulses included); the left step τ^{n-1/2} scales it.
  const double tau_v = 0.5 * (st.dt_prev + st.dt);
  const double w = tau_v > 0.0 ? st.dt_prev / tau_v : 0.0;
  for (std::size_t i = 0; i < st.x.size(); ++i) {
    s.kinetic += 0.5 * st.m[i] * st.v[i].dot(st.v[i] + w * (st.v_star[i] - st.v[i]));
    s.mass += st.m[i];
    const Vec3 p = 0.5 * st.m[i] * (st.v[i] + st.v_star[i]);
    s.momentum += p;
    s.momentum_scale += p.norm();
    s.bc_impulse_now += st.bc_impulse[i];
    power_behind += st.bc_impulse[i].dot(st.v[i]);
    s.bc_power_ahead += st.bc_impulse[i].dot(st.v_star[i]);
  }
  for (double e : st.e_int) s.internal += e;
  // Centred momentum moves by ½ (J^n + J^{n+1}) between samples (internal forces cancel).
  if (previous) {
    s.boundary_work = previous->boundary_work + 0.5 * (previous->bc_power_ahead + power_behind);
    s.boundary_impulse =
        previous->boundary_impulse + 0.5 * (previous->bc_impulse_now + s.bc_impulse_now);
  }
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
