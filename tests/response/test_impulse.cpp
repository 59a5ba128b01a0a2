// The impulse kernel: momentum exact, push only, the seed's eq. (11) in its 2 + 2 form.
#include <gtest/gtest.h>

#include <random>

#include "contact_points.hpp"
#include "tetcontact/response/impulse.hpp"

using namespace tc;

namespace {

State random_state(std::mt19937& rng, int n) {
  std::uniform_real_distribution<double> u(-1, 1), m(0.5, 2.0);
  State st;
  for (int i = 0; i < n; ++i) {
    st.x.push_back(Vec3(u(rng), u(rng), u(rng)));
    st.v_star.push_back(Vec3(u(rng), u(rng), u(rng)));
    st.m.push_back(m(rng));
  }
  return st;
}

Vec3 momentum(const State& st) {
  Vec3 p = Vec3::Zero();
  for (std::size_t i = 0; i < st.m.size(); ++i) p += st.m[i] * st.v_star[i];
  return p;
}

}  // namespace

TEST(Impulse, ConservesMomentumAndEnforcesTheNormalVelocity) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  for (int k = 0; k < 100; ++k) {
    State st = random_state(rng, 4);
    std::vector<Vec3> ledger(4, Vec3::Zero());
    const double w1 = u(rng), w2 = (1 - w1) * u(rng);
    ContactPoint c = test::node_against_face(0, {1, 2, 3}, w1, w2);
    c.normal = Vec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5).normalized();
    c.gap = k % 2 ? 0.0 : 1e-3;
    const double tau = 1e-3;
    const Vec3 p0 = momentum(st);
    const double lambda = apply_contact(c, st, tau, ledger);
    EXPECT_GE(lambda, 0.0);  // from a zero accumulated impulse: a push
    EXPECT_LT((momentum(st) - p0).norm(), 1e-14);
    EXPECT_LT((ledger[0] + ledger[1] + ledger[2] + ledger[3]).norm(), 1e-14);
    const Vec3 v_rel = st.v_star[0] - (c.b_w[0] * st.v_star[1] + c.b_w[1] * st.v_star[2] +
                                       c.b_w[2] * st.v_star[3]);
    const double target = c.gap >= 0 ? -c.gap / tau : 0.0;
    EXPECT_GE(v_rel.dot(c.normal), target - 1e-12);  // no interpenetration within the step
    if (lambda > 0) {
      EXPECT_NEAR(v_rel.dot(c.normal), target, 1e-12);  // and no more push
    }
    // Already satisfied: nothing more than round-off.
    EXPECT_LE(apply_contact(c, st, tau, ledger), 1e-12 * (1.0 + lambda));
  }
}

// The normal velocity a contact ends with, against its target worked by hand: gap g, rounding
// separation s = 1e-9, stand-off δ = 1e-6, τ = 1e-6: closing from farther it stops δ beyond s,
// v = (s + δ − g)/τ; within the stand-off a pair with push speed 0 is held (v = 0) and one with
// push speed v_p separates at v_p (0.25 m/s) when (s + δ − g)/τ exceeds it, at (s + δ − g)/τ
// when not; through by more than s, a node–face pair is held and a restoring one pushed at v_p,
// or faster where that would not put it s apart within the step.
TEST(Impulse, TheStandOffStopsClosingPairsAndPushesBackOnlyAtThePushSpeed) {
  const double tau = 1e-6, s = 1e-9, delta = 1e-6, vp = 0.25;
  struct Case {
    double gap, push, expected;
    bool restore;
  };
  const Case cases[] = {
      {3e-6, 0.0, (s + delta - 3e-6) / tau, false},    // closing from farther: stops at s + δ
      {3e-6, vp, (s + delta - 3e-6) / tau, true},      // the same, restoring
      {0.5e-6, 0.0, 0.0, false},                       // within the stand-off, held
      {0.5e-6, vp, vp, true},                          // pushed back at v_p (0.5 m/s asked)
      {0.9e-6, vp, (s + delta - 0.9e-6) / tau, true},  // 0.101 m/s asked: below v_p
      {0.0, 0.0, s / tau, false},                      // touching: put s apart
      {-1e-7, 0.0, 0.0, false},                        // a node in deeper than s: held
      {-1e-7, vp, vp, true},                           // restoring: at v_p (s asks 0.101)
      {-1e-6, vp, (s + 1e-6) / tau, true},             // s asks 1.001 m/s: s apart
  };
  for (const Case& k : cases) {
    State st;
    st.m = {1.0, 1.0};
    st.v_star = {Vec3(0, 0, -3), Vec3::Zero()};  // closing at 3 m/s
    std::vector<Vec3> ledger(2, Vec3::Zero());
    ContactPoint c = test::node_against_node(0, 1);
    c.gap = k.gap, c.separation = s, c.standoff = delta, c.push_speed = k.push;
    c.restore = k.restore;
    apply_contact(c, st, tau, ledger);
    EXPECT_NEAR((st.v_star[0] - st.v_star[1]).z(), k.expected, 1e-12)
        << "gap " << k.gap << " push " << k.push;
  }
}

// Dobritsa et al. eq. (11)–(12), edge [a, b] of body 1 against edge [e, f] of body 2 at parameters
// α, β: N_c = [(1−α)U*_na + αU*_nb − (1−β)U*_ne − βU*_nf] / (τ Σ w²/m), and the corrected
// normal velocities of the two contact points are equal. The kernel with weights
// (1−α, α) and (1−β, β) is exactly that (the normal from body 2 to body 1).
TEST(Impulse, EdgeEdgeIsTheSeedsEquationEleven) {
  std::mt19937 rng(11);
  State st = random_state(rng, 4);  // a, b, e, f
  const double alpha = 0.3, beta = 0.6, tau = 1e-6;
  ContactPoint c;
  c.a_nodes = {0, 1, 0, 0};
  c.a_w = {1 - alpha, alpha, 0, 0};
  c.a_count = 2;
  c.b_nodes = {2, 3, 0, 0};
  c.b_w = {1 - beta, beta, 0, 0};
  c.b_count = 2;
  c.normal = Vec3(0, 0, 1);
  // Make the edges approach: body 1 (a, b) moving down onto body 2.
  st.v_star[0].z() = st.v_star[1].z() = -3.0;
  st.v_star[2].z() = st.v_star[3].z() = 1.0;
  const double una = st.v_star[0].z(), unb = st.v_star[1].z(), une = st.v_star[2].z(),
               unf = st.v_star[3].z();
  const double sum = (1 - beta) * (1 - beta) / st.m[2] + beta * beta / st.m[3] +
                     (1 - alpha) * (1 - alpha) / st.m[0] + alpha * alpha / st.m[1];
  const double n_c =
      ((1 - alpha) * una + alpha * unb - (1 - beta) * une - beta * unf) / (tau * sum);
  std::vector<Vec3> ledger(4, Vec3::Zero());
  const double lambda = apply_contact(c, st, tau, ledger);
  // Eq. (11)'s N_c is a force pulling edge [a, b] back: our impulse is −τ N_c.
  EXPECT_NEAR(lambda, -tau * n_c, 1e-12 * std::abs(tau * n_c));
  // Eq. (12) with m_b (the misprint corrected): U_nb^{n+1} = U*_nb − τ α N_c / m_b.
  EXPECT_NEAR(st.v_star[1].z(), unb - tau * alpha * n_c / st.m[1], 1e-12);
  EXPECT_NEAR(st.v_star[3].z(), unf + tau * beta * n_c / st.m[3], 1e-12);
  const double ud = (1 - alpha) * st.v_star[0].z() + alpha * st.v_star[1].z();
  const double uc = (1 - beta) * st.v_star[2].z() + beta * st.v_star[3].z();
  EXPECT_NEAR(ud, uc, 1e-12);  // eq. (8)
}

TEST(Impulse, StickRemovesTheSlidingAndCoulombLimitsIt) {
  for (FrictionMode mode : {FrictionMode::stick, FrictionMode::coulomb}) {
    State st;
    st.x = {Vec3::Zero(), Vec3::Zero()};
    st.v_star = {Vec3(4, 0, -1), Vec3(0, 0, 1)};
    st.m = {1.0, 1.0};
    std::vector<Vec3> ledger(2, Vec3::Zero());
    ContactPoint c = test::node_against_node(0, 1);
    c.normal = Vec3(0, 0, 1);
    c.mode = mode;
    c.friction = 0.5;
    apply_contact(c, st, 1e-3, ledger);
    const Vec3 rel = st.v_star[0] - st.v_star[1];
    EXPECT_NEAR(rel.z(), 0.0, 1e-12);  // normal: equal velocities (λ = 1)
    if (mode == FrictionMode::stick) {
      EXPECT_NEAR(rel.x(), 0.0, 1e-12);
    } else {
      // Tangential impulse limited to k λ = 0.5: the relative sliding 4 drops by 0.5 (1/m_a +
      // 1/m_b).
      EXPECT_NEAR(rel.x(), 3.0, 1e-12);
    }
  }
}
