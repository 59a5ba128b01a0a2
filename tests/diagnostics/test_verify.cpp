// The step verification: passes from apart, through, touching and sliding, touching
// and going on through, and particles, against motions whose answer is known by construction.
#include <gtest/gtest.h>

#include <cmath>

#include "../solver/solver_fixture.hpp"
#include "tetcontact/diagnostics/verify.hpp"

using namespace tc;

namespace {

// Two unit cubes (2 × 2 × 2 cells), b on top of a: b's bottom face at z = 0.5 + gap.
Model stacked(double gap) {
  Model m;
  add_body(m.mesh, "a", make_box(Vec3(1, 1, 1), {2, 2, 2}, HexSplit::six));
  TetMesh b = make_box(Vec3(1, 1, 1), {2, 2, 2}, HexSplit::six);
  translate(b, Vec3(0.1, 0.2, 1.0 + gap));  // staggered sideways: faces do not match
  add_body(m.mesh, "b", b);
  m.surfaces = build_surfaces(m.mesh);
  return m;
}

std::vector<Vec3> moved(const Model& m, const Vec3& d) {  // body b moved by d
  std::vector<Vec3> x = m.mesh.x;
  for (Index i = m.mesh.bodies[1].node_begin; i < m.mesh.bodies[1].node_end; ++i) x[i] += d;
  return x;
}

}  // namespace

TEST(Verify, ApproachingAndStoppingShortPassesGoingThroughFails) {
  const Model m = stacked(0.1);
  StepVerifier verifier(m.mesh);
  const Index end = static_cast<Index>(m.mesh.x.size());
  Verification v = verifier.verify(m.surfaces, m.mesh.x, moved(m, Vec3(0, 0, -0.099)), end);
  EXPECT_TRUE(v.failed.empty());
  // Through by 0.05: b's bottom nodes pass a's top faces, b's edges cross a's edges.
  v = verifier.verify(m.surfaces, m.mesh.x, moved(m, Vec3(0, 0, -0.15)), end);
  EXPECT_GT(v.pairs_checked, static_cast<long>(v.failed.size()));
  ASSERT_FALSE(v.failed.empty());
  bool vf = false, ee = false;
  for (const FailedPair& p : v.failed) {
    EXPECT_FALSE(p.touching_at_start);
    EXPECT_GE(p.count, 4);
    (p.edge_edge ? ee : vf) = true;
    // One side of each pair in each body.
    int in_b = 0;
    for (int k = 0; k < 4; ++k) in_b += p.nodes[k] >= m.mesh.bodies[1].node_begin;
    EXPECT_TRUE(p.edge_edge ? in_b == 2 : (in_b == 1 || in_b == 3));
  }
  EXPECT_TRUE(vf);
  EXPECT_TRUE(ee);
  // Tunnelling: through the whole cube and out below within the step still fails.
  v = verifier.verify(m.surfaces, m.mesh.x, moved(m, Vec3(0, 0, -3.0)), end);
  EXPECT_FALSE(v.failed.empty());
}

TEST(Verify, TouchingIsAllowedGoingOnThroughIsNot) {
  const Model m = stacked(0.0);  // b's bottom face lies on a's top face
  StepVerifier verifier(m.mesh);
  const Index end = static_cast<Index>(m.mesh.x.size());
  // Resting, sliding in the plane, lifting off: touching and staying in touch.
  for (const Vec3& d : {Vec3(0, 0, 0), Vec3(0.05, -0.03, 0), Vec3(0, 0, 0.01)}) {
    const Verification v = verifier.verify(m.surfaces, m.mesh.x, moved(m, d), end);
    EXPECT_TRUE(v.failed.empty()) << d.transpose();
  }
  // 2^-40 m on through: a's top nodes under b's faces end strictly inside b's tets.
  const Verification v =
      verifier.verify(m.surfaces, m.mesh.x, moved(m, Vec3(0, 0, -std::ldexp(1.0, -40))), end);
  ASSERT_FALSE(v.failed.empty());
  for (const FailedPair& p : v.failed) EXPECT_TRUE(p.touching_at_start);
}

TEST(Verify, ParticlesAreVerticesOfNoBody) {
  Model m = stacked(0.5);
  StepVerifier verifier(m.mesh);
  const Index first_particle = static_cast<Index>(m.mesh.x.size());
  std::vector<Vec3> x0 = m.mesh.x, x1 = m.mesh.x;
  x0.push_back(Vec3(0.1, 0.3, 0.6));  // above a's top face, off its triangles' edges
  x1.push_back(Vec3(0.1, 0.3, 0.4));  // through it
  Verification v = verifier.verify(m.surfaces, x0, x1, first_particle);
  ASSERT_EQ(v.failed.size(), 1u);
  EXPECT_EQ(v.failed[0].nodes[0], first_particle);
  EXPECT_FALSE(v.failed[0].edge_edge);
  x1.back() = Vec3(0.1, 0.3, 0.55);  // stops short
  v = verifier.verify(m.surfaces, x0, x1, first_particle);
  EXPECT_TRUE(v.failed.empty());
}
