// Exact CCD: known answers, degenerate configurations, and the shared query set.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "../test_util.hpp"
#include "tetcontact/app/float_ccd.hpp"
#include "tetcontact/narrowphase/exact_ccd.hpp"
#include "tetcontact/narrowphase/vertex_face.hpp"

using namespace tc;

namespace {

std::array<Vec3, 8> vf(const Vec3& p0, const Vec3& a0, const Vec3& b0, const Vec3& c0,
                       const Vec3& p1, const Vec3& a1, const Vec3& b1, const Vec3& c1) {
  return {p0, a0, b0, c0, p1, a1, b1, c1};
}

// The query restricted to the sub-step [0, s] (end positions rounded to doubles).
std::array<Vec3, 8> until(std::array<Vec3, 8> q, double s) {
  for (int k = 0; k < 4; ++k) q[4 + k] = q[k] + s * (q[4 + k] - q[k]);
  return q;
}

}  // namespace

TEST(ExactCcd, VertexFaceKnownAnswers) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  // Crossing at t = 0.3; beside; parallel above.
  EXPECT_TRUE(
      exact_vertex_face_ccd(vf(Vec3(0.2, 0.2, 0.3), a, b, c, Vec3(0.2, 0.2, -0.7), a, b, c)));
  EXPECT_FALSE(
      exact_vertex_face_ccd(vf(Vec3(0.8, 0.8, 0.3), a, b, c, Vec3(0.8, 0.8, -0.7), a, b, c)));
  EXPECT_FALSE(
      exact_vertex_face_ccd(vf(Vec3(0.2, 0.2, 0.1), a, b, c, Vec3(0.3, 0.2, 0.1), a, b, c)));
  // Touching exactly at t = 1 (counts), and at t = 0 on an edge (counts).
  EXPECT_TRUE(exact_vertex_face_ccd(vf(Vec3(0.2, 0.2, 1), a, b, c, Vec3(0.2, 0.2, 0), a, b, c)));
  EXPECT_TRUE(exact_vertex_face_ccd(vf(Vec3(0.5, 0, 0), a, b, c, Vec3(0.5, -1, 1), a, b, c)));
  // Stopping a hair above the face: no contact, however small the gap.
  EXPECT_FALSE(
      exact_vertex_face_ccd(vf(Vec3(0.2, 0.2, 1), a, b, c, Vec3(0.2, 0.2, 0x1p-1000), a, b, c)));
  // Coplanar all step, sliding into the triangle from outside: a collision.
  EXPECT_TRUE(exact_vertex_face_ccd(vf(Vec3(-1, 0.2, 0), a, b, c, Vec3(0.2, 0.2, 0), a, b, c)));
  // Coplanar all step, sliding past it: none.
  EXPECT_FALSE(exact_vertex_face_ccd(vf(Vec3(-1, -0.2, 0), a, b, c, Vec3(2, -0.2, 0), a, b, c)));
  // A degenerate (collinear) triangle swept over the point.
  EXPECT_TRUE(
      exact_vertex_face_ccd(vf(Vec3(0.5, 0.5, 0), Vec3(0, 0, -1), Vec3(1, 1, -1), Vec3(2, 2, -1),
                               Vec3(0.5, 0.5, 0), Vec3(0, 0, 1), Vec3(1, 1, 1), Vec3(2, 2, 1))));
}

TEST(ExactCcd, EdgeEdgeKnownAnswers) {
  // Perpendicular edges passing through each other at t = 0.5.
  const auto q = [](double z0, double z1) {
    return std::array<Vec3, 8>{Vec3(-1, 0, 0), Vec3(1, 0, 0), Vec3(0, -1, z0), Vec3(0, 1, z0),
                               Vec3(-1, 0, 0), Vec3(1, 0, 0), Vec3(0, -1, z1), Vec3(0, 1, z1)};
  };
  EXPECT_TRUE(exact_edge_edge_ccd(q(1, -1)));
  EXPECT_TRUE(exact_edge_edge_ccd(q(1, 0)));          // touching at t = 1
  EXPECT_FALSE(exact_edge_edge_ccd(q(1, 0x1p-900)));  // stopping just short
  // Parallel edges sliding along one line into overlap (coplanar all step): a collision.
  EXPECT_TRUE(
      exact_edge_edge_ccd({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(3, 0, 0), Vec3(4, 0, 0),
                           Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 0, 0), Vec3(1.5, 0, 0)}));
  // Parallel edges one unit apart, never meeting.
  EXPECT_FALSE(
      exact_edge_edge_ccd({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0),
                           Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 1, 0), Vec3(1.5, 1, 0)}));
  // A zero-length edge (a point) passing through the other edge.
  EXPECT_TRUE(
      exact_edge_edge_ccd({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 0, 1), Vec3(0.5, 0, 1),
                           Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 0, -1), Vec3(0.5, 0, -1)}));
}

// Generic random queries (no degeneracy): the exact answer and the floating-point crossing
// test agree.
TEST(ExactCcd, AgreesWithFloatingPointOnGenericQueries) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  int hits = 0;
  for (int k = 0; k < 300; ++k) {
    std::array<Vec3, 8> q;
    for (Vec3& p : q) p = Vec3(u(rng), u(rng), u(rng));
    const bool exact = exact_vertex_face_ccd(q);
    const bool fp = vertex_face_ccd(q[0], q[1], q[2], q[3], q[4], q[5], q[6], q[7]).has_value();
    EXPECT_EQ(exact, fp) << k;
    hits += exact;
  }
  EXPECT_GT(hits, 10);
}

// data/ccd/handcrafted.txt: 7,279 degenerate queries with exact ground truth (the handcrafted
// scenes of Wang et al. 2021's CCD benchmark, MIT licence, shipped with the project). A missing
// file fails the test.
TEST(ExactCcd, HandcraftedQuerySetHasNoFalsePositivesOrNegatives) {
  const std::string file = test::source_path("data/ccd/handcrafted.txt");
  ASSERT_TRUE(std::filesystem::exists(file)) << "missing data file " << file;
  test::TempDir dir("ccd-handcrafted");
  const auto r = test::run_cli("ccd '" + file + "' --json --fcl", dir.str());
  ASSERT_EQ(r.code, 0) << r.err;
  const test::Json j = test::Json::parse(r.out);
  // The set's own counts (data/ccd/README.md), ours exact, and FCL 0.7's cubic solver beside
  // it with the errors ../shared/ANCHORS.md states for it (26 / 25 on ee, 111 / 7 on vf).
  struct Expected {
    const char* type;
    double queries, collisions, fcl_fp, fcl_fn;
  };
  for (const Expected& e : {Expected{"ee", 4194, 187, 26, 25}, Expected{"vf", 3085, 248, 111, 7}}) {
    SCOPED_TRACE(e.type);
    const test::Json& t = j.at(e.type);
    EXPECT_EQ(test::number(t, "/queries"), e.queries);
    EXPECT_EQ(test::number(t, "/collisions"), e.collisions);
    EXPECT_EQ(test::number(t, "/false_positives"), 0);
    EXPECT_EQ(test::number(t, "/false_negatives"), 0);
    EXPECT_EQ(test::number(t, "/fcl/false_positives"), e.fcl_fp);
    EXPECT_EQ(test::number(t, "/fcl/false_negatives"), e.fcl_fn);
  }
}

// Earliest time of impact: analytical answers, including the coplanar-all-step cases.
TEST(ExactCcd, TimeOfImpactKnownAnswers) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  // Through the face: z = 0.25 − t.
  EXPECT_EQ(
      exact_vertex_face_toi(vf(Vec3(0.2, 0.2, 0.25), a, b, c, Vec3(0.2, 0.2, -0.75), a, b, c)),
      0.25);
  // Touching at t = 0 and at t = 1.
  EXPECT_EQ(exact_vertex_face_toi(vf(Vec3(0.5, 0, 0), a, b, c, Vec3(0.5, -1, 1), a, b, c)), 0.0);
  EXPECT_EQ(exact_vertex_face_toi(vf(Vec3(0.2, 0.2, 1), a, b, c, Vec3(0.2, 0.2, 0), a, b, c)), 1.0);
  EXPECT_FALSE(
      exact_vertex_face_toi(vf(Vec3(0.8, 0.8, 0.3), a, b, c, Vec3(0.8, 0.8, -0.7), a, b, c)));
  // Coplanar all step, x = −1 + 1.2 t enters the triangle at x = 0: t = 5/6.
  EXPECT_NEAR(*exact_vertex_face_toi(vf(Vec3(-1, 0.2, 0), a, b, c, Vec3(0.2, 0.2, 0), a, b, c)),
              5.0 / 6.0, 2e-16);  // rounded down: within one ulp
  // Collinear edges: [3 − 2.5 t, 4 − 2.5 t] reaches [0, 1] at t = 4/5.
  EXPECT_NEAR(
      *exact_edge_edge_toi({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(3, 0, 0), Vec3(4, 0, 0),
                            Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 0, 0), Vec3(1.5, 0, 0)}),
      0.8, 2e-16);  // rounded down: within one ulp
  // A tilting face: c(t) = (0, 1, 2t), so the plane is z = 2t·y. A falling point
  // (0.25, 0.25, 1 − t) meets it at 1 − t = 0.5 t, t = 2/3; one that also moves in y,
  // y = 0.25 + 0.25 t, meets it at t² + 3t − 2 = 0, t = (√17 − 3)/2 (irrational).
  const Vec3 c1(0, 1, 2);
  EXPECT_NEAR(
      *exact_vertex_face_toi(vf(Vec3(0.25, 0.25, 1), a, b, c, Vec3(0.25, 0.25, 0), a, b, c1)),
      2.0 / 3.0, 2e-16);  // rounded down: within one ulp
  const auto t =
      exact_vertex_face_toi(vf(Vec3(0.25, 0.25, 1), a, b, c, Vec3(0.25, 0.5, 0), a, b, c1));
  ASSERT_TRUE(t);
  EXPECT_NEAR(*t, (std::sqrt(17.0) - 3) / 2, 2e-16);
}

// The earliest time is the earliest: on random hits, the exact query restricted to the
// sub-step [0, t(1 − 1e−6)] finds no collision, and on [0, t(1 + 1e−6)] it does.
TEST(ExactCcd, TimeOfImpactIsTheEarliestCollision) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  int checked = 0;
  for (int k = 0; k < 400 && checked < 40; ++k) {
    std::array<Vec3, 8> q;
    for (Vec3& p : q) p = Vec3(u(rng), u(rng), u(rng));
    for (int type = 0; type < 2; ++type) {
      const auto toi = type ? exact_edge_edge_toi(q) : exact_vertex_face_toi(q);
      const bool hit = type ? exact_edge_edge_ccd(q) : exact_vertex_face_ccd(q);
      ASSERT_EQ(toi.has_value(), hit) << k;
      if (!toi || *toi < 1e-3 || *toi > 1 - 1e-3) continue;
      const auto before = until(q, *toi * (1 - 1e-6)), after = until(q, *toi * (1 + 1e-6));
      EXPECT_FALSE(type ? exact_edge_edge_ccd(before) : exact_vertex_face_ccd(before)) << k;
      EXPECT_TRUE(type ? exact_edge_edge_ccd(after) : exact_vertex_face_ccd(after)) << k;
      ++checked;
    }
  }
  EXPECT_GE(checked, 40);
}

// Motions that stay in the plane z = 0 all step (the cubic vanishes identically): the same
// check, on points snapped to a grid of 1/8 so that segments often touch, run over and lie
// on each other. Many hits are single instants of touching, which the rounded sub-step
// [0, t(1 + 1e−6)] can miss, so that half of the check is asked of most, not all.
TEST(ExactCcd, CoplanarMotionTimeOfImpactIsTheEarliestCollision) {
  std::mt19937 rng(12);
  std::uniform_int_distribution<int> u(-8, 8);
  int checked = 0, hits = 0, misses = 0, found_after = 0;
  for (int k = 0; k < 2000; ++k) {
    std::array<Vec3, 8> q;
    for (Vec3& p : q) p = Vec3(u(rng) / 8.0, u(rng) / 8.0, 0.0);
    for (int type = 0; type < 2; ++type) {
      const auto toi = type ? exact_edge_edge_toi(q) : exact_vertex_face_toi(q);
      const bool hit = type ? exact_edge_edge_ccd(q) : exact_vertex_face_ccd(q);
      ASSERT_EQ(toi.has_value(), hit) << k;
      hits += hit;
      misses += !hit;
      if (!toi || *toi < 1e-3 || *toi > 1 - 1e-3) continue;
      const auto before = until(q, *toi * (1 - 1e-6)), after = until(q, *toi * (1 + 1e-6));
      EXPECT_FALSE(type ? exact_edge_edge_ccd(before) : exact_vertex_face_ccd(before)) << k;
      found_after += type ? exact_edge_edge_ccd(after) : exact_vertex_face_ccd(after);
      ++checked;
    }
  }
  EXPECT_GE(checked, 200);
  EXPECT_GE(found_after, 0.95 * checked);
  EXPECT_GE(misses, 200);
  EXPECT_GE(hits, 200);
}

// `ccd --toi` prints the time after each hit; a bad line names the file and line.
TEST(ExactCcd, CliPrintsTimeOfImpactAndRejectsBadLines) {
  test::TempDir dir("ccd-toi");
  const std::string file = dir.str() + "/q.txt";
  test::write_text(file,
                   "vf 0.2 0.2 0.25  0 0 0  1 0 0  0 1 0  0.2 0.2 -0.75  0 0 0  1 0 0  0 1 0\n"
                   "vf 1 0.8 0.8 0.3  0 0 0  1 0 0  0 1 0  0.8 0.8 -0.7  0 0 0  1 0 0  0 1 0\n");
  auto r = test::run_cli("ccd '" + file + "' --toi", dir.str());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.out.substr(0, r.out.find("ee:")), "1 0.25\n0\n");
  EXPECT_NE(r.out.find("1 false negatives"), std::string::npos) << r.out;  // its GT said 1
  test::write_text(file, "vf 1 2 3\n");
  r = test::run_cli("ccd '" + file + "' --toi", dir.str());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("q.txt:1: expected 24 coordinates"), std::string::npos) << r.err;
}

namespace {

// 2-D predicates on small integers, written apart from the exact CCD: orientation of (a, b, p),
// p on the closed segment [a, b], closed segments meeting, p in the closed triangle.
using P2 = std::array<long long, 2>;
long long orient(const P2& a, const P2& b, const P2& p) {
  return (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]);
}
bool on_segment_2d(const P2& p, const P2& a, const P2& b) {
  return orient(a, b, p) == 0 && std::min(a[0], b[0]) <= p[0] && p[0] <= std::max(a[0], b[0]) &&
         std::min(a[1], b[1]) <= p[1] && p[1] <= std::max(a[1], b[1]);
}
bool segments_meet_2d(const P2& a, const P2& b, const P2& c, const P2& d) {
  const long long o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a),
                  o4 = orient(c, d, b);
  const auto sg = [](long long x) { return (x > 0) - (x < 0); };
  if (sg(o1) * sg(o2) < 0 && sg(o3) * sg(o4) < 0) return true;
  return on_segment_2d(c, a, b) || on_segment_2d(d, a, b) || on_segment_2d(a, c, d) ||
         on_segment_2d(b, c, d);
}
bool in_triangle_2d(const P2& p, const P2& a, const P2& b, const P2& c) {
  const long long area = orient(a, b, c);
  if (area == 0) return on_segment_2d(p, a, b) || on_segment_2d(p, b, c) || on_segment_2d(p, c, a);
  const long long s = area > 0 ? 1 : -1;
  return s * orient(a, b, p) >= 0 && s * orient(b, c, p) >= 0 && s * orient(c, a, p) >= 0;
}

}  // namespace

// Queries with no motion (the verification's "touching at the start") take their own exact
// path. Points on a 4 × 4 grid of one plane (collinear, touching, overlapping and shared points
// common), placed by exact maps (axis permutation and signs, integer offset, scale 2^e): the
// answer of the 2-D integer predicates above; and the same query moved by a common exact
// translation, which keeps every relation and goes through the general path.
TEST(ExactCcd, QueriesWithoutMotionMatchTwoDimensionalPredicatesAndTranslatedMotions) {
  std::mt19937_64 rng(17);
  std::uniform_int_distribution<int> grid(0, 3), offset(-1000, 1000), scale(-30, 30), coin(0, 1);
  long hits[2] = {0, 0}, total[2] = {0, 0};
  for (int n = 0; n < 4000; ++n) {
    const bool ee = n % 2 == 0;
    std::array<P2, 4> p2;
    for (P2& p : p2) p = {grid(rng), grid(rng)};
    const bool truth = ee ? segments_meet_2d(p2[0], p2[1], p2[2], p2[3])
                          : in_triangle_2d(p2[0], p2[1], p2[2], p2[3]);
    std::array<int, 3> axis{0, 1, 2};
    std::shuffle(axis.begin(), axis.end(), rng);
    const Vec3 shift(offset(rng), offset(rng), offset(rng));
    const double s = std::ldexp(1.0, scale(rng));
    const double sign[3] = {coin(rng) ? 1.0 : -1.0, coin(rng) ? 1.0 : -1.0, coin(rng) ? 1.0 : -1.0};
    std::array<Vec3, 8> q, moved;
    const Vec3 step(offset(rng), offset(rng), offset(rng));  // the common translation
    for (int k = 0; k < 4; ++k) {
      Vec3 x;
      x[axis[0]] = sign[0] * p2[k][0];
      x[axis[1]] = sign[1] * p2[k][1];
      x[axis[2]] = sign[2] * 7.0;  // the plane
      q[k] = q[k + 4] = s * (x + shift);
      moved[k] = q[k];
      moved[k + 4] = s * (x + shift + step);
    }
    const bool fast = ee ? exact_edge_edge_ccd(q) : exact_vertex_face_ccd(q);
    const bool general = ee ? exact_edge_edge_ccd(moved) : exact_vertex_face_ccd(moved);
    EXPECT_EQ(fast, truth) << "query " << n;
    EXPECT_EQ(general, truth) << "translated query " << n;
    hits[ee] += truth;
    ++total[ee];
  }
  // Both answers are common: the set tests something.
  for (int ee = 0; ee < 2; ++ee) {
    EXPECT_GT(hits[ee], total[ee] / 10);
    EXPECT_LT(hits[ee], total[ee] * 9 / 10);
  }
}

// The shortcuts (fixed-width integers of 4, 6 or 8 words picked by the spread of the query's
// exponents, signs at the roots certified in doubles) against GMP's integers and the exact sign
// test throughout: the same answer, the same answer with every filter off (the exact
// path alone) and the same time of impact, on the shared degenerate set and on variants of it
// scaled by powers of two and with its zero coordinates moved to 2^-30, 2^-60 and 2^-90 (spreads
// that pick each width and, the last, GMP's).
TEST(ExactCcd, ShortcutsGiveThePlainExactPathsAnswersAndTimes) {
  const std::string file = test::source_path("data/ccd/handcrafted.txt");
  std::ifstream in(file);
  ASSERT_TRUE(in) << "missing data file " << file;
  struct Query {
    bool ee;
    std::array<Vec3, 8> q;
  };
  std::vector<Query> queries;
  std::string line;
  for (int n = 0; std::getline(in, line); ++n) {
    std::istringstream ss(line);
    std::string type;
    ss >> type;
    std::vector<double> v;
    for (std::string tok; ss >> tok;) v.push_back(std::strtod(tok.c_str(), nullptr));
    ASSERT_EQ(v.size(), 25u) << file << ":" << n + 1;
    Query base{type == "ee", {}};
    for (int k = 0; k < 8; ++k) base.q[k] = Vec3(v[1 + 3 * k], v[2 + 3 * k], v[3 + 3 * k]);
    queries.push_back(base);
    if (n % 5 != 0) continue;
    for (const int s : {-40, 3, 60}) {
      Query scaled = base;
      for (Vec3& p : scaled.q) p *= std::ldexp(1.0, s);
      queries.push_back(scaled);
    }
    for (const int s : {-30, -60, -90}) {
      Query moved = base;
      for (Vec3& p : moved.q)
        for (int d = 0; d < 3; ++d)
          if (p[d] == 0.0) p[d] = std::ldexp(1.0, s);
      queries.push_back(moved);
    }
  }
  ASSERT_GT(queries.size(), 15000u);
  const CcdFilters off{false, false, false};
  const auto answers = [&](bool fixed) {
    set_exact_ccd_shortcuts(fixed);
    std::vector<double> out;
    for (const Query& x : queries) {
      const bool yes = x.ee ? exact_edge_edge_ccd(x.q) : exact_vertex_face_ccd(x.q);
      const bool alone = x.ee ? exact_edge_edge_ccd(x.q, off) : exact_vertex_face_ccd(x.q, off);
      const std::optional<double> t = x.ee ? exact_edge_edge_toi(x.q) : exact_vertex_face_toi(x.q);
      EXPECT_EQ(yes, alone);
      EXPECT_EQ(yes, t.has_value());
      out.push_back(yes ? 2.0 : 0.0);
      out.push_back(alone ? 2.0 : 0.0);
      out.push_back(t.value_or(-1.0));
    }
    set_exact_ccd_shortcuts(true);
    return out;
  };
  const std::vector<double> fixed = answers(true), gmp = answers(false);
  ASSERT_EQ(fixed.size(), gmp.size());
  long differ = 0, hits = 0;
  for (std::size_t k = 0; k < fixed.size(); ++k) {
    differ += fixed[k] != gmp[k];
    hits += k % 3 == 0 && fixed[k] > 0.0;
  }
  EXPECT_EQ(differ, 0);
  EXPECT_GT(hits, 900);  // the variants keep many of the set's collisions
}
