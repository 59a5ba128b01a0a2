// The certified interval filter in front of the exact CCD: never contradicts the exact answer,
// and decides generic queries by itself.
#include <gtest/gtest.h>

#include <random>

#include "tetcontact/narrowphase/exact_ccd.hpp"
#include "tetcontact/narrowphase/interval_ccd.hpp"

using namespace tc;

// Random queries (points in [−1, 1]³ at both ends; in every other one points 2 and 3 sweep
// through the middle of points 0 and 1, so that many collide): the filter's yes/no equals the exact
// answer, and "unknown" is rare on such generic input.
TEST(IntervalCcd, AgreesWithExactAndDecidesGenericQueries) {
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> u(-1, 1);
  int decided = 0, total = 0, hits = 0;
  for (int k = 0; k < 4000; ++k) {
    std::array<Vec3, 8> q;
    for (Vec3& p : q) p = Vec3(u(rng), u(rng), u(rng));
    if (k % 2) {  // points 0, 1 stay; points 2, 3 sweep through the centre of 0 and 1
      const Vec3 shift = (q[0] + q[1]) - (q[2] + q[3]);
      for (int n = 0; n < 4; ++n) q[4 + n] = q[n] + (n < 2 ? Vec3::Zero() : shift);
    }
    for (int type = 0; type < 2; ++type) {
      const Certain c = type ? interval_edge_edge_ccd(q) : interval_vertex_face_ccd(q);
      const bool exact = type ? exact_edge_edge_ccd(q) : exact_vertex_face_ccd(q);
      ++total;
      hits += exact;
      if (c == Certain::unknown) continue;
      ++decided;
      EXPECT_EQ(c == Certain::yes, exact) << "query " << k << " type " << type;
    }
  }
  EXPECT_GT(hits, total / 20);
  EXPECT_GE(decided, 0.995 * total);  // 100 % measured
}

// Exactly touching configurations are never claimed: a vertex landing on a face's edge, an edge
// landing on another at its endpoint, and a motion coplanar all step.
TEST(IntervalCcd, TouchingAndCoplanarMotionAreLeftToTheExactPath) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  EXPECT_EQ(interval_vertex_face_ccd({Vec3(0.5, 0, 1), a, b, c, Vec3(0.5, 0, -1), a, b, c}),
            Certain::unknown);
  EXPECT_EQ(interval_edge_edge_ccd(
                {a, b, Vec3(1, -1, 1), Vec3(1, 1, 1), a, b, Vec3(1, -1, -1), Vec3(1, 1, -1)}),
            Certain::unknown);
  EXPECT_EQ(interval_vertex_face_ccd({Vec3(-1, 0.2, 0), a, b, c, Vec3(0.2, 0.2, 0), a, b, c}),
            Certain::unknown);
  EXPECT_TRUE(exact_vertex_face_ccd({Vec3(0.5, 0, 1), a, b, c, Vec3(0.5, 0, -1), a, b, c}));
  // Clear cases are decided.
  EXPECT_EQ(interval_vertex_face_ccd({Vec3(0.2, 0.2, 1), a, b, c, Vec3(0.2, 0.2, -1), a, b, c}),
            Certain::yes);
  EXPECT_EQ(interval_vertex_face_ccd({Vec3(0.8, 0.8, 1), a, b, c, Vec3(0.8, 0.8, -1), a, b, c}),
            Certain::no);
}
