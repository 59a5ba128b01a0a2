// The contact point the step's verification gives a failing pair sits where the pair
// first meets during the step, not at its closest points at the start: scenes whose closest
// points at xⁿ are an end of an edge or a point on a face's edge, with the exact answer known.
#include <gtest/gtest.h>

#include <vector>

#include "tetcontact/mesh/surface.hpp"
#include "tetcontact/model/state.hpp"
#include "tetcontact/narrowphase/contact.hpp"

using namespace tc;

namespace {

// Two one-tet bodies (nodes 0–3 and 4–7); the tests place the nodes themselves.
struct Scene {
  Mesh mesh;
  std::vector<Surface> surfaces;
  State st;
  Scene() {
    const TetMesh tet{{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)}, {{0, 1, 2, 3}}};
    add_body(mesh, "a", tet);
    add_body(mesh, "b", tet);
    surfaces = build_surfaces(mesh);
    st.x = mesh.x;
  }
};

}  // namespace

// Edge A from (0,0,1)–(2,0,1) moves by (3, 0, −2) across edge B (3,−1,0)–(3,1,0): they meet at
// t = 1/2 at (3, 0, 0), three quarters along A and halfway along B. At the start the closest
// points are A's end (2,0,1) and B's middle.
TEST(RescuePoint, EdgePairIsPlacedWhereTheEdgesFirstMeet) {
  Scene s;
  s.st.x[0] = Vec3(0, 0, 1), s.st.x[1] = Vec3(2, 0, 1);
  s.st.x[4] = Vec3(3, -1, 0), s.st.x[5] = Vec3(3, 1, 0);
  s.st.x_star = s.st.x;
  std::vector<Vec3> x1 = s.st.x;
  x1[0] += Vec3(3, 0, -2), x1[1] += Vec3(3, 0, -2);
  const ContactDetection contact(s.mesh, s.surfaces, ContactSettings{}, 0.0);
  const auto c =
      contact.edge_edge_point(s.st, x1, {0, 1}, {4, 5}, 0, 1, Vec3::Zero(), Vec3::Zero());
  ASSERT_TRUE(c.has_value());
  EXPECT_NEAR(c->a_w[0], 0.25, 1e-12);
  EXPECT_NEAR(c->a_w[1], 0.75, 1e-12);
  EXPECT_NEAR(c->b_w[0], 0.5, 1e-12);
  EXPECT_NEAR(c->b_w[1], 0.5, 1e-12);
  EXPECT_NEAR((c->normal - Vec3(0, 0, 1)).norm(), 0.0, 1e-12);  // from B towards A at the start
  EXPECT_NEAR(c->gap, 1.0, 1e-12);
}

// Node 0 moves from (2, 0.2, 1) to (−1.6, 0.2, −1) through the face (4,5,6) = (0,0,0), (1,0,0),
// (0,1,0) at t = 1/2, at (0.2, 0.2, 0): weights (0.6, 0.2, 0.2). At the start its closest point
// on the face lies on the face's edge from (1,0,0) to (0,1,0).
TEST(RescuePoint, VertexFacePairIsPlacedWhereTheVertexCrossesTheFace) {
  Scene s;
  s.st.x[0] = Vec3(2, 0.2, 1);
  s.st.x[4] = Vec3(0, 0, 0), s.st.x[5] = Vec3(1, 0, 0), s.st.x[6] = Vec3(0, 1, 0);
  s.st.x_star = s.st.x;
  std::vector<Vec3> x1 = s.st.x;
  x1[0] = Vec3(-1.6, 0.2, -1);
  const ContactDetection contact(s.mesh, s.surfaces, ContactSettings{}, 0.0);
  const auto c = contact.vertex_face_point(s.st, x1, 0, {4, 5, 6}, 0, 1);
  ASSERT_TRUE(c.has_value());
  EXPECT_NEAR(c->b_w[0], 0.6, 1e-12);
  EXPECT_NEAR(c->b_w[1], 0.2, 1e-12);
  EXPECT_NEAR(c->b_w[2], 0.2, 1e-12);
  EXPECT_NEAR((c->normal - Vec3(0, 0, 1)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(c->gap, 1.0, 1e-12);
}
