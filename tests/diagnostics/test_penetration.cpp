// The penetration diagnostics against configurations of known overlap.
#include <gtest/gtest.h>

#include <cmath>

#include "../solver/solver_fixture.hpp"
#include "tetcontact/diagnostics/penetration.hpp"

using namespace tc;

namespace {

Model two_cubes(double offset, const Vec3& sideways = Vec3::Zero()) {
  Model model;
  add_body(model.mesh, "a", make_box(Vec3(1, 1, 1), {4, 4, 4}, HexSplit::six));
  TetMesh b = make_box(Vec3(1, 1, 1), {4, 4, 4}, HexSplit::six);
  translate(b, Vec3(offset, 0, 0) + sideways);
  add_body(model.mesh, "b", b);
  model.materials = {test::aluminium()};
  model.body_material = {0, 0};
  model.surfaces = build_surfaces(model.mesh);
  return model;
}

}  // namespace

TEST(Penetration, OverlappingCubesHaveTheirDepthAndCrossings) {
  // b's left face at x = 0.4 is 0.1 inside a (a's right face at x = 0.5); b is shifted
  // sideways so that its edges cross a's faces inside them, not through a's vertices.
  const Model m = two_cubes(0.9, Vec3(0, 0.1, 0.07));
  PenetrationProbe probe(m);
  const Penetration p = probe.measure(m.mesh.x);
  EXPECT_NEAR(p.max_depth, 0.1, 1e-12);
  EXPECT_NEAR(p.max_depth_over_h, 0.1 / m.surfaces[0].mean_edge_length, 1e-12);
  EXPECT_GT(p.nodes_inside, 0);
  EXPECT_GT(p.crossings, 0);
  // b's edges along x cross a's face x = 0.5 at points 0.05–0.125 inside a's triangles.
  EXPECT_GT(p.max_crossing_depth, 0.01);
  EXPECT_LT(p.max_crossing_depth, 0.25);
  // The deepest nodes are b's nodes on x = 0.4 away from a's sides.
  for (Index i = m.mesh.bodies[1].node_begin; i < m.mesh.bodies[1].node_end; ++i) {
    const Vec3& x = m.mesh.x[i];
    if (std::abs(x.x() - 0.4) < 1e-12 && std::abs(x.y() - 0.1) < 0.3 &&
        std::abs(x.z() - 0.07) < 0.3) {
      EXPECT_NEAR(p.node_depth[i], 0.1, 1e-12);
    }
  }
}

TEST(Penetration, TouchingAndSeparatedCubesHaveNone) {
  for (double offset : {1.0, 1.5}) {  // faces touching exactly; apart
    const Model m = two_cubes(offset);
    PenetrationProbe probe(m);
    const Penetration p = probe.measure(m.mesh.x);
    EXPECT_EQ(p.nodes_inside, 0) << offset;
    EXPECT_EQ(p.max_depth, 0.0) << offset;
    EXPECT_EQ(p.crossings, 0) << offset;  // an edge lying in a touching face does not cross it
  }
}

TEST(Penetration, NodesOnAnotherBodysFaceTouchAndOneUlpBelowAreInside) {
  // A 5 × 5 mesh on a 4 × 4 one, faces coincident at z = 0: the upper nodes lie on the lower
  // triangles, where the floating-point distance to the face is ~1e-19 m, not 0.
  Model m;
  TetMesh lower = make_box(Vec3(0.01, 0.01, 0.01), {4, 4, 4}, HexSplit::six);
  translate(lower, Vec3(0, 0, -0.005));
  TetMesh upper = make_box(Vec3(0.01, 0.01, 0.01), {5, 5, 4}, HexSplit::six);
  translate(upper, Vec3(0, 0, 0.005));
  add_body(m.mesh, "lower", lower);
  add_body(m.mesh, "upper", upper);
  m.materials = {test::aluminium()};
  m.body_material = {0, 0};
  m.surfaces = build_surfaces(m.mesh);
  PenetrationProbe probe(m);
  Penetration p = probe.measure(m.mesh.x);
  EXPECT_EQ(p.nodes_inside, 0);
  EXPECT_EQ(p.max_depth, 0.0);
  EXPECT_EQ(p.crossings, 0);
  // One upper node moved down by 2^-60 m (8.7e-19) is inside.
  std::vector<Vec3> x = m.mesh.x;
  Index moved = -1;
  for (Index i = m.mesh.bodies[1].node_begin; i < m.mesh.bodies[1].node_end && moved < 0; ++i)
    if (x[i].z() == 0.0 && std::abs(x[i].x() - 0.001) < 1e-12 && std::abs(x[i].y() - 0.001) < 1e-12)
      moved = i;
  ASSERT_GE(moved, 0);
  x[moved].z() = -std::ldexp(1.0, -60);
  p = probe.measure(x);
  // It is inside; so are the lower nodes under the faces it pulled down with it.
  EXPECT_GT(p.node_depth[moved], 0.0);
  EXPECT_LT(p.node_depth[moved], 1e-18);
  EXPECT_GE(p.nodes_inside, 1);
  EXPECT_EQ(p.deepest_node_body + p.deepest_in_body, 1);  // one body's node in the other
}

TEST(Penetration, ExactPredicatesOnTheBoundary) {
  EXPECT_TRUE(
      exact_point_on_triangle(Vec3(0.3, 0.3, 0), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)));
  EXPECT_TRUE(
      exact_point_on_triangle(Vec3(0.5, 0.5, 0), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)));
  EXPECT_FALSE(
      exact_point_on_triangle(Vec3(0.3, 0.3, 1e-300), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)));
  EXPECT_FALSE(
      exact_point_on_triangle(Vec3(0.6, 0.6, 0), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)));
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0), d(0, 0, 1);
  EXPECT_TRUE(exact_point_in_tet(Vec3(0.25, 0.25, 0.25), a, b, c, d));
  EXPECT_TRUE(exact_point_in_tet(Vec3(0.5, 0.5, 0.0), a, b, c, d));  // on a face
  EXPECT_FALSE(exact_point_in_tet(Vec3(0.5, 0.5, 1e-300), a, b, c, d));
  EXPECT_TRUE(exact_segment_crosses_triangle(Vec3(0.2, 0.2, -1), Vec3(0.2, 0.2, 1), a, b, c));
  EXPECT_FALSE(exact_segment_crosses_triangle(Vec3(0.2, 0.2, 0), Vec3(0.2, 0.2, 1), a, b, c));
  EXPECT_FALSE(exact_segment_crosses_triangle(Vec3(0.6, 0.6, -1), Vec3(0.6, 0.6, 1), a, b, c));
  // Through the triangle's edge or vertex: it touches, it does not cross.
  EXPECT_FALSE(exact_segment_crosses_triangle(Vec3(0.5, 0.0, -1), Vec3(0.5, 0.0, 1), a, b, c));
  EXPECT_FALSE(exact_segment_crosses_triangle(Vec3(0, 0, -1), Vec3(0, 0, 1), a, b, c));
}

// One probe measuring at every step of b sliding into a and turning (its binding lists kept
// while nothing has moved past the reach) against a new probe at each step (a fresh search):
// the same measures, node by node, bit for bit; and the lists did last.
TEST(Penetration, BindingListsMeasureWhatAFreshSearchMeasures) {
  const Model m = two_cubes(1.05, Vec3(0, 0.1, 0.07));
  PenetrationProbe kept(m);
  std::vector<Vec3> x = m.mesh.x;
  long inside = 0, crossings = 0;
  for (int k = 0; k < 60; ++k) {
    const double angle = 0.002 * k;
    for (Index i = m.mesh.bodies[1].node_begin; i < m.mesh.bodies[1].node_end; ++i) {
      const Vec3 p = m.mesh.x[i] - Vec3(0.004 * k, 0, 0);
      x[i] = Vec3(p.x(), std::cos(angle) * p.y() - std::sin(angle) * p.z(),
                  std::sin(angle) * p.y() + std::cos(angle) * p.z());
    }
    const Penetration a = kept.measure(x);
    PenetrationProbe fresh(m);
    const Penetration b = fresh.measure(x);
    ASSERT_EQ(a.node_depth, b.node_depth) << "step " << k;
    ASSERT_EQ(a.nodes_inside, b.nodes_inside);
    ASSERT_EQ(a.max_depth, b.max_depth);
    ASSERT_EQ(a.crossings, b.crossings);
    ASSERT_EQ(a.max_crossing_depth, b.max_crossing_depth);
    ASSERT_EQ(a.deepest_node_body, b.deepest_node_body);
    ASSERT_EQ(a.crossing_edge_body, b.crossing_edge_body);
    inside += a.nodes_inside;
    crossings += a.crossings;
  }
  EXPECT_GT(inside, 100);  // b ends 0.19 inside a: there is something to agree on
  EXPECT_GT(crossings, 100);
  EXPECT_GT(kept.searches(), 1);
  EXPECT_LT(kept.searches(), 30);
}
