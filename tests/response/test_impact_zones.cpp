// Rigid impact zones: the rigid field keeps linear and angular momentum, never adds kinetic
// energy, books its impulses, and the zones are the connected sets of the merged nodes.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>

#include "tetcontact/response/impact_zones.hpp"

using namespace tc;

namespace {

State random_state(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0), m(0.5, 2.0);
  State st;
  for (int i = 0; i < n; ++i) {
    st.x.push_back(Vec3(u(rng), u(rng), u(rng)));
    st.v_star.push_back(Vec3(u(rng), u(rng), u(rng)) * 100.0);
    st.m.push_back(m(rng));
  }
  return st;
}

struct Moments {
  Vec3 p = Vec3::Zero(), l = Vec3::Zero();
  double kinetic = 0.0;
};
Moments moments(const State& st, const std::vector<Index>& nodes) {
  Moments r;
  for (const Index i : nodes) {
    r.p += st.m[i] * st.v_star[i];
    r.l += st.m[i] * st.x[i].cross(st.v_star[i]);
    r.kinetic += 0.5 * st.m[i] * st.v_star[i].squaredNorm();
  }
  return r;
}

}  // namespace

TEST(ImpactZones, RigidFieldKeepsBothMomentaAndLowersKineticEnergy) {
  for (unsigned seed = 1; seed <= 20; ++seed) {
    State st = random_state(12, seed);
    const std::vector<Index> zone = {0, 1, 2, 3, 4, 5, 6, 7};  // 8, 9, 10, 11 stay out
    const Moments before = moments(st, zone);
    const std::vector<Vec3> u = st.v_star;
    ImpactZones zones;
    zones.reset(st.x.size());
    const std::array<Index, 4> a{0, 1, 2, 3}, b{3, 4, 5, 6}, c{6, 7, 7, 7};
    zones.merge(a.data(), 4);
    zones.merge(b.data(), 4);
    zones.merge(c.data(), 4);
    std::vector<Vec3> ledger(st.x.size(), Vec3::Zero());
    zones.apply(u, st, ledger);
    const Moments after = moments(st, zone);
    const double scale = before.p.norm() + 1.0;
    EXPECT_LT((after.p - before.p).norm(), 1e-12 * scale) << seed;
    EXPECT_LT((after.l - before.l).norm(), 1e-12 * (before.l.norm() + scale)) << seed;
    EXPECT_LE(after.kinetic, before.kinetic * (1.0 + 1e-14)) << seed;
    // The field is rigid: every pair's relative velocity is normal to their separation.
    for (const Index i : zone)
      for (const Index j : zone)
        EXPECT_NEAR((st.v_star[i] - st.v_star[j]).dot(st.x[i] - st.x[j]), 0.0, 1e-10) << seed;
    // The ledger holds m ΔU; nodes outside the zone are untouched.
    for (Index i = 0; i < 12; ++i) {
      EXPECT_LT((ledger[i] - st.m[i] * (st.v_star[i] - u[i])).norm(), 1e-12 * scale);
      if (i >= 8) {
        EXPECT_EQ(st.v_star[i], u[i]);
      }
    }
  }
}

TEST(ImpactZones, ACollinearZoneKeepsItsAngularMomentum) {
  // Two nodes: the inertia is singular along their line; the pseudo-inverse keeps L.
  State st;
  st.x = {Vec3(0, 0, 0), Vec3(1, 0, 0)};
  st.v_star = {Vec3(1, 2, 0), Vec3(-1, -2, 3)};
  st.m = {1.0, 3.0};
  const Moments before = moments(st, {0, 1});
  ImpactZones zones;
  zones.reset(2);
  const std::array<Index, 2> pair{0, 1};
  zones.merge(pair.data(), 2);
  std::vector<Vec3> ledger(2, Vec3::Zero());
  zones.apply(st.v_star, st, ledger);
  const Moments after = moments(st, {0, 1});
  EXPECT_LT((after.p - before.p).norm(), 1e-14);
  EXPECT_LT((after.l - before.l).norm(), 1e-14);
  EXPECT_LT(after.kinetic, before.kinetic);
  EXPECT_TRUE(std::isfinite(st.v_star[0].norm()));
}

TEST(ImpactZones, ZonesAreTheConnectedSetsAndFreezingFollowsMerges) {
  ImpactZones zones;
  zones.reset(10);
  const std::array<Index, 2> a{1, 2}, b{5, 6}, c{2, 7};
  EXPECT_FALSE(zones.merge(a.data(), 2));
  EXPECT_FALSE(zones.merge(b.data(), 2));
  EXPECT_TRUE(zones.merge(a.data(), 2));  // already one zone
  EXPECT_TRUE(zones.same_zone(a.data(), 2));
  EXPECT_FALSE(zones.same_zone(c.data(), 2));
  using Motion = ImpactZones::Motion;
  zones.escalate(5);
  EXPECT_EQ(zones.motion(6), Motion::translated);
  zones.escalate(6);
  EXPECT_EQ(zones.motion(5), Motion::frozen);
  zones.escalate(6);  // frozen is the last
  EXPECT_EQ(zones.motion(5), Motion::frozen);
  EXPECT_EQ(zones.motion(1), Motion::rigid);
  zones.merge(c.data(), 2);
  auto z = zones.zones();
  ASSERT_EQ(z.size(), 2u);
  EXPECT_EQ(z[0].nodes, (std::vector<Index>{1, 2, 7}));
  EXPECT_EQ(z[0].motion, Motion::rigid);
  EXPECT_EQ(z[1].nodes, (std::vector<Index>{5, 6}));
  EXPECT_EQ(z[1].motion, Motion::frozen);
  // A merge with a frozen zone is frozen; a reset forgets everything.
  const std::array<Index, 2> d{7, 6};
  zones.merge(d.data(), 2);
  z = zones.zones();
  ASSERT_EQ(z.size(), 1u);
  EXPECT_EQ(z[0].motion, Motion::frozen);
  zones.reset(10);
  EXPECT_TRUE(zones.zones().empty());
  EXPECT_EQ(zones.motion(6), Motion::rigid);
}

TEST(ImpactZones, ExactTranslationKeepsRelativePositionsBitForBit) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    const double scale = std::ldexp(1.0, trial % 40 - 20);
    std::vector<Vec3> x;
    std::vector<Index> nodes;
    for (int i = 0; i < 6; ++i) {
      x.push_back(Vec3(u(rng), u(rng), u(rng)) * scale + Vec3(0.3, -2.0, 5.0));
      nodes.push_back(i);
    }
    const Vec3 want = Vec3(u(rng), u(rng), u(rng)) * scale * 1e-3;
    std::array<bool, 3> exact{};
    const Vec3 d = exact_translation(x, nodes, want, &exact);
    for (int k = 0; k < 3; ++k) {
      // Each axis: the wanted shift to within the grain where exact, else 0.
      if (exact[k]) {
        EXPECT_LT(std::abs(d[k] - want[k]), 1e-12 * scale + 1e-15);
      } else {
        EXPECT_EQ(d[k], 0.0);
      }
    }
    // A shift below half the grain is exact and 0; one that carries a node's coordinate into
    // a coarser binade, with its low bits set, is not exact.
    std::array<bool, 3> tiny{};
    EXPECT_EQ(exact_translation(x, nodes, Vec3::Constant(1e-30), &tiny), Vec3::Zero());
    EXPECT_TRUE(tiny[0] && tiny[1] && tiny[2]);
    for (const Index i : nodes)
      for (const Index j : nodes) {
        const Vec3 before = x[i] - x[j], after = (x[i] + d) - (x[j] + d);
        EXPECT_EQ(before, after) << trial;  // differences of the moved points: unchanged
        for (int k = 0; k < 3; ++k)         // and each sum exact
          EXPECT_EQ((x[i][k] + d[k]) - d[k], x[i][k]);
      }
  }
}
