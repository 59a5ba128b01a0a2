#include "tetcontact/response/impulse.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tc {

namespace {

Vec3 point_velocity(const std::array<Index, 4>& nodes, const std::array<double, 4>& w, int n,
                    const State& st) {
  Vec3 v = Vec3::Zero();
  for (int i = 0; i < n; ++i) v += w[i] * st.v_star[nodes[i]];
  return v;
}

void push(ContactPoint& c, const Vec3& impulse_on_a, State& st, std::vector<Vec3>& ledger) {
  for (int i = 0; i < c.a_count; ++i) {
    const Vec3 j = c.a_w[i] * impulse_on_a;
    st.v_star[c.a_nodes[i]] += j / st.m[c.a_nodes[i]];
    ledger[c.a_nodes[i]] += j;
  }
  for (int i = 0; i < c.b_count; ++i) {
    const Vec3 j = c.b_w[i] * impulse_on_a;
    st.v_star[c.b_nodes[i]] -= j / st.m[c.b_nodes[i]];
    ledger[c.b_nodes[i]] -= j;
  }
}

// The normal velocity v* a contact aims at (apply_contact): the gap s + δ at the end of the
// step, v* = (s + δ − g)/τ; a push apart (v* > 0) is limited to the push speed beyond what
// reaches the rounding margin s, v* ≤ max(v_push, (s − g)/τ).
double target_velocity(const ContactPoint& c, double tau) {
  if (c.gap < -c.separation && !c.restore) return 0.0;
  const double target = (c.separation + c.standoff - c.gap) / tau;
  if (target <= c.push_speed) return target;
  return std::max(c.push_speed, (c.separation - c.gap) / tau);
}

// A's point velocity less B's: Σ w_A U_A − Σ w_B U_B.
Vec3 relative_velocity(const ContactPoint& c, const State& st) {
  return point_velocity(c.a_nodes, c.a_w, c.a_count, st) -
         point_velocity(c.b_nodes, c.b_w, c.b_count, st);
}

}  // namespace

double apply_contact(ContactPoint& c, State& st, double tau, std::vector<Vec3>& ledger) {
  if (c.inv_mass < 0.0) {  // Σ w²/m over both sides, once a step
    double sum = 0.0;
    for (int i = 0; i < c.a_count; ++i) sum += c.a_w[i] * c.a_w[i] / st.m[c.a_nodes[i]];
    for (int i = 0; i < c.b_count; ++i) sum += c.b_w[i] * c.b_w[i] / st.m[c.b_nodes[i]];
    c.inv_mass = sum > 0.0 ? sum : 0.0;  // NaN (a massless node): no exchange
  }
  const double inv_mass = c.inv_mass;
  if (!(inv_mass > 0.0)) return 0.0;
  const Vec3& n = c.normal;
  const Vec3 v_rel = relative_velocity(c, st);
  const double target = target_velocity(c, tau);
  // The accumulated impulse of the step pushes, never pulls: an increment may take back what
  // earlier passes over-pushed (the corrections of neighbouring contacts move shared nodes),
  // but the total stays ≥ 0 (projected Gauss–Seidel).
  const double accumulated = std::max(0.0, c.lambda + (target - v_rel.dot(n)) / inv_mass);
  const double lambda = accumulated - c.lambda;
  if (lambda != 0.0) {
    push(c, lambda * n, st, ledger);
    c.lambda = accumulated;
    // The pair's kinetic energy changes by λ (v_n + v_n') / 2, v_n' = v_n + λ Σ w²/m.
    const double vn = v_rel.dot(n);
    c.heat -= 0.5 * lambda * (2.0 * vn + lambda * inv_mass);
  }
  if (c.mode == FrictionMode::slip || c.lambda <= 0.0) return lambda;
  // Tangential: the impulse that stops the relative sliding, limited for Coulomb.
  const Vec3 v_now = point_velocity(c.a_nodes, c.a_w, c.a_count, st) -
                     point_velocity(c.b_nodes, c.b_w, c.b_count, st);
  const Vec3 vt = v_now - v_now.dot(n) * n;
  Vec3 total = c.tangential - vt / inv_mass;  // accumulated impulse needed to stick
  if (c.mode == FrictionMode::coulomb) {
    const double limit = c.friction * c.lambda, size = total.norm();
    if (size > limit) total *= limit / size;
  }
  const Vec3 delta = total - c.tangential;
  if (delta.squaredNorm() > 0.0) {
    push(c, delta, st, ledger);
    c.tangential = total;
    c.heat -= delta.dot(v_now) + 0.5 * delta.squaredNorm() * inv_mass;  // likewise, sliding
  }
  return lambda;
}

}  // namespace tc
