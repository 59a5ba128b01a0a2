#include <gtest/gtest.h>

#include <random>

#include "tetcontact/narrowphase/vertex_face.hpp"

using namespace tc;

TEST(Narrowphase, PointInTetSignTest) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0), d(0, 0, 1);
  EXPECT_TRUE(point_in_tet(Vec3(0.2, 0.2, 0.2), a, b, c, d));
  EXPECT_TRUE(point_in_tet(a, a, b, c, d));                    // a vertex counts
  EXPECT_TRUE(point_in_tet(Vec3(0.5, 0.5, 0.0), a, b, c, d));  // on a face
  EXPECT_FALSE(point_in_tet(Vec3(0.5, 0.5, 0.1), a, b, c, d));
  EXPECT_FALSE(point_in_tet(Vec3(-1e-9, 0.2, 0.2), a, b, c, d));
}

TEST(Narrowphase, ClosestPointOnTriangleMatchesSampling) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int k = 0; k < 200; ++k) {
    const Vec3 a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng)), c(u(rng), u(rng), u(rng));
    const Vec3 p(2 * u(rng), 2 * u(rng), 2 * u(rng));
    const TrianglePoint r = closest_point_on_triangle(p, a, b, c);
    EXPECT_NEAR(r.w[0] + r.w[1] + r.w[2], 1.0, 1e-12);
    for (double w : r.w) EXPECT_GE(w, -1e-12);
    EXPECT_NEAR((p - (r.w[0] * a + r.w[1] * b + r.w[2] * c)).norm(), r.distance, 1e-12);
    double best = 1e300;  // brute force over a barycentric grid
    const int n = 60;
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) {
        const double wb = double(i) / n, wc = double(j) / n;
        best = std::min(best, (p - ((1 - wb - wc) * a + wb * b + wc * c)).norm());
      }
    EXPECT_LE(r.distance, best + 1e-12);
    EXPECT_GE(r.distance, best - 0.05);  // the grid's resolution
  }
}

TEST(Narrowphase, BehindFaceWithinTheLayer) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);  // normal +z
  EXPECT_TRUE(behind_face(Vec3(0.2, 0.2, -0.01), a, b, c, 0.1));
  EXPECT_TRUE(behind_face(Vec3(0.2, 0.2, 0.0), a, b, c, 0.1));       // on the face
  EXPECT_FALSE(behind_face(Vec3(0.2, 0.2, 0.01), a, b, c, 0.1));     // in front
  EXPECT_FALSE(behind_face(Vec3(0.2, 0.2, -0.2), a, b, c, 0.1));     // deeper than the layer
  EXPECT_TRUE(behind_face(Vec3(-1e-6, 0.5, -0.01), a, b, c, 0.1));   // rim, within 1e-3 of an edge
  EXPECT_FALSE(behind_face(Vec3(-0.01, 0.5, -0.01), a, b, c, 0.1));  // beside the face
}

// The rim tolerance is a distance from the face, 1e-3 of its longest edge, whatever its shape:
// beyond a short edge (here 1e-3 of the longest) and past a sharp corner as beside a long
// edge. Random points near slivers: all that is accepted lies within that distance of the
// triangle's box (what the contact search's layer box holds), and the tolerance's edge is sharp.
TEST(Narrowphase, BehindFaceRimIsADistanceFromTheFace) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(1, 1e-3, 0);  // |bc| = 1e-3 L, angle at a 0.057°
  EXPECT_TRUE(behind_face(Vec3(1 + 0.9e-3, 0.5e-3, -0.01), a, b, c, 0.1));
  EXPECT_FALSE(behind_face(Vec3(1 + 1.1e-3, 0.5e-3, -0.01), a, b, c, 0.1));
  EXPECT_TRUE(behind_face(Vec3(-0.9e-3, 0, -0.01), a, b, c, 0.1));  // past the sharp corner
  EXPECT_FALSE(behind_face(Vec3(-1.1e-3, 0, -0.01), a, b, c, 0.1));
  unsigned seed = 7;
  const auto uniform = [&](double lo, double hi) {
    seed = seed * 1664525u + 1013904223u;
    return lo + (hi - lo) * (seed >> 8) / double(1u << 24);
  };
  int accepted = 0;
  for (int k = 0; k < 20000; ++k) {
    const Vec3 p(uniform(-0.01, 1.01), uniform(-0.01, 0.011), uniform(-0.02, 0.001));
    if (!behind_face(p, a, b, c, 0.1)) continue;
    ++accepted;
    EXPECT_TRUE(p.x() >= -1e-3 && p.x() <= 1 + 1e-3 && p.y() >= -1e-3 && p.y() <= 2e-3)
        << p.transpose();
  }
  EXPECT_GT(accepted, 100);
}
