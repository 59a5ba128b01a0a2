#include "tetcontact/solver/integrator.hpp"

#include "tetcontact/parallel/parallel.hpp"

namespace tc {

void predict(State& st, const std::vector<VelocityConstraint>& constraints) {
  const double tau_v = 0.5 * (st.dt_prev + st.dt);
  const std::size_t n = st.x.size();
  // A node left without cells (all turned into particles) has no mass and no force.
  parallel::for_each(
      n,
      [&](std::size_t i) {
        st.v_star[i] = st.m[i] > 0.0 ? Vec3(st.v[i] + (tau_v / st.m[i]) * st.f[i]) : st.v[i];
        st.bc_impulse[i].setZero();
      },
      parallel::k_light_block);
  hold_constraints(st, constraints);
  parallel::for_each(
      n, [&](std::size_t i) { st.x_star[i] = st.x[i] + st.dt * st.v_star[i]; },
      parallel::k_light_block);
}

void hold_constraints(State& st, const std::vector<VelocityConstraint>& constraints) {
  for (const VelocityConstraint& c : constraints)
    for (Index node : c.nodes)
      for (int d = 0; d < 3; ++d)
        if (c.components[d]) {
          st.bc_impulse[node][d] += st.m[node] * (c.velocity[d] - st.v_star[node][d]);
          st.v_star[node][d] = c.velocity[d];
        }
}

void commit(State& st) {
  const std::size_t n = st.x.size();
  parallel::for_each(
      n,
      [&](std::size_t i) {
        st.v[i] = st.v_star[i];
        st.x[i] += st.dt * st.v[i];
      },
      parallel::k_light_block);
  st.t += st.dt;
  st.dt_prev = st.dt;
  ++st.step;
}

}  // namespace tc
