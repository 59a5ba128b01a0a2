// The sphere meshed by Delaunay refinement (CGAL Mesh_3 behind mesh_ball).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "tetcontact/mesh/delaunay.hpp"
#include "tetcontact/mesh/generators.hpp"
#include "tetcontact/mesh/surface.hpp"

namespace tc {
namespace {

constexpr double k_radius = 5e-3;

Mesh one_body(TetMesh t) {
  Mesh m;
  add_body(m, "ball", std::move(t));
  return m;
}

// Circumradius and circumcentre of a tet: the centre c solves 2 (p_i − p_0)·c = |p_i|² − |p_0|².
std::pair<double, Vec3> circumsphere(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  Mat3 m;
  m.row(0) = 2.0 * (b - a);
  m.row(1) = 2.0 * (c - a);
  m.row(2) = 2.0 * (d - a);
  const Vec3 rhs(b.squaredNorm() - a.squaredNorm(), c.squaredNorm() - a.squaredNorm(),
                 d.squaredNorm() - a.squaredNorm());
  const Vec3 centre = m.fullPivLu().solve(rhs);
  return {(a - centre).norm(), centre};
}

TEST(DelaunayBall, ClosedSurfaceOnTheSpherePositiveCells) {
  const Mesh m = one_body(mesh_ball(k_radius, BallSizing{1.25e-3}));
  ASSERT_GT(m.tet_count(), 200);
  double volume = 0.0, worst_angle = 180.0;
  for (const Tet& t : m.tets) {
    const double v = tet_signed_volume(m.x[t[0]], m.x[t[1]], m.x[t[2]], m.x[t[3]]);
    EXPECT_GT(v, 0.0);
    volume += v;
    worst_angle =
        std::min(worst_angle, min_dihedral_angle_deg(m.x[t[0]], m.x[t[1]], m.x[t[2]], m.x[t[3]]));
  }
  // An inscribed polyhedron whose facets stay within a fifth of the cell size δ of the sphere
  // (the facet distance criterion): it holds the ball of radius R − δ.
  const double ball = 4.0 / 3.0 * M_PI * std::pow(k_radius, 3);
  EXPECT_LT(volume, ball);
  EXPECT_GT(volume, std::pow(1.0 - 0.2 * 1.25e-3 / k_radius, 3) * ball);
  EXPECT_GT(worst_angle, 5.0) << "exudation leaves no worse sliver";
  const std::vector<Surface> s = build_surfaces(m);
  ASSERT_EQ(s.size(), 1u);
  EXPECT_EQ(s[0].euler_characteristic(), 2);
  for (const Index n : s[0].nodes) EXPECT_NEAR(m.x[n].norm(), k_radius, 1e-15);
  // Every node not on the surface is inside.
  std::vector<char> on_surface(m.x.size(), 0);
  for (const Index n : s[0].nodes) on_surface[n] = 1;
  for (std::size_t n = 0; n < m.x.size(); ++n)
    EXPECT_TRUE(on_surface[n] || m.x[n].norm() < k_radius) << "node " << n;
}

// The size field h = min(cell, refine + growth·d) bounds every cell's circumradius at its
// circumcentre (Mesh_3's criterion; exudation may stretch a cell slightly, hence 1.25), and
// the cells near the refinement point are that small.
TEST(DelaunayBall, CellsFollowTheSizeField) {
  const BallSizing s{1.0e-3, Vec3(0, 0, -1), 5.0e-5, 0.3};
  const Mesh m = one_body(mesh_ball(k_radius, s));
  const Vec3 pole(0, 0, -k_radius);
  double largest_near_pole = 0.0, largest = 0.0;
  for (const Tet& t : m.tets) {
    const auto [r, c] = circumsphere(m.x[t[0]], m.x[t[1]], m.x[t[2]], m.x[t[3]]);
    const double h = std::min(s.cell_size, s.refine_size + s.growth * (c - pole).norm());
    EXPECT_LT(r, 1.25 * h);
    largest = std::max(largest, r);
    if ((m.x[t[0]] - pole).norm() < 1e-4) largest_near_pole = std::max(largest_near_pole, r);
  }
  EXPECT_GT(largest_near_pole, 0.0);
  EXPECT_LT(largest_near_pole, 1.25 * (s.refine_size + s.growth * 2e-4));
  EXPECT_GT(largest, 10.0 * largest_near_pole);
}

TEST(DelaunayBall, SameMeshEveryRun) {
  const BallSizing s{1.0e-3, Vec3(1, 1, 0), 1.0e-4, 0.3};
  const TetMesh a = mesh_ball(k_radius, s), b = mesh_ball(k_radius, s);
  ASSERT_EQ(a.x.size(), b.x.size());
  ASSERT_EQ(a.tets.size(), b.tets.size());
  EXPECT_TRUE(std::equal(a.x.begin(), a.x.end(), b.x.begin()));
  EXPECT_TRUE(std::equal(a.tets.begin(), a.tets.end(), b.tets.begin()));
}

TEST(DelaunayBall, SizesOutOfRangeAreRefused) {
  const auto message = [](double radius, const BallSizing& s) -> std::string {
    try {
      mesh_ball(radius, s);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_NE(message(k_radius, {1e-2}).find("cell_size must be in (0, radius]"), std::string::npos);
  EXPECT_NE(message(k_radius, {1e-3, Vec3(1, 0, 0), 2e-3}).find("refine_size"), std::string::npos);
  EXPECT_NE(message(k_radius, {1e-3, Vec3(1, 0, 0), 1e-4, 0.0}).find("growth"), std::string::npos);
  // About 1e8 cells asked for: refused before meshing, with the estimate.
  EXPECT_NE(message(k_radius, {1e-5}).find("more than 5 million"), std::string::npos);
}

}  // namespace
}  // namespace tc
