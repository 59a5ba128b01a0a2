// The step verification: passes from apart, through, touching and sliding, touching
// and going on through, and particles, against motions whose answer is known by construction;
// its pairs against a brute-force search, and a verification again after some nodes moved
// against a fresh one.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <set>

#include "../solver/solver_fixture.hpp"
#include "tetcontact/verify/verify.hpp"

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

// What the verifier reads of a run: the positions xⁿ (and `particles` particles after the
// mesh's nodes, radius 0.01), the surfaces, and the detection's candidates (grid, binding lists
// with the verification's edges).
struct Scene {
  explicit Scene(const Model& model, std::vector<Vec3> x0 = {}, int particles = 0) : m(model) {
    st.x = x0.empty() ? m.mesh.x : std::move(x0);
    st.first_particle = static_cast<Index>(m.mesh.x.size());
    st.particle_radius.assign(static_cast<std::size_t>(particles), 0.01);
    st.surfaces = m.surfaces;
    CandidateSettings c;
    c.broadphase = "grid";
    c.verify = true;
    c.particles = particles > 0;
    candidates = std::make_unique<ContactCandidates>(m.mesh, m.surfaces, c);
  }
  Verification verify(StepVerifier& v, const std::vector<Vec3>& x1) {
    return v.verify(st, x1, *candidates);
  }
  const Model& m;
  State st;
  std::unique_ptr<ContactCandidates> candidates;
};

}  // namespace

TEST(Verify, ApproachingAndStoppingShortPassesGoingThroughFails) {
  const Model m = stacked(0.1);
  Scene scene(m);
  StepVerifier verifier(m.mesh);
  Verification v = scene.verify(verifier, moved(m, Vec3(0, 0, -0.099)));
  EXPECT_TRUE(v.failed.empty());
  // Through by 0.05: b's bottom nodes pass a's top faces, b's edges cross a's edges.
  v = scene.verify(verifier, moved(m, Vec3(0, 0, -0.15)));
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
  v = scene.verify(verifier, moved(m, Vec3(0, 0, -3.0)));
  EXPECT_FALSE(v.failed.empty());
}

TEST(Verify, TouchingIsAllowedGoingOnThroughIsNot) {
  const Model m = stacked(0.0);  // b's bottom face lies on a's top face
  Scene scene(m);
  StepVerifier verifier(m.mesh);
  // Resting, sliding in the plane, lifting off: touching and staying in touch.
  for (const Vec3& d : {Vec3(0, 0, 0), Vec3(0.05, -0.03, 0), Vec3(0, 0, 0.01)}) {
    const Verification v = scene.verify(verifier, moved(m, d));
    EXPECT_TRUE(v.failed.empty()) << d.transpose();
  }
  // 2^-40 m on through: a's top nodes under b's faces end strictly inside b's tets.
  const Verification v = scene.verify(verifier, moved(m, Vec3(0, 0, -std::ldexp(1.0, -40))));
  ASSERT_FALSE(v.failed.empty());
  for (const FailedPair& p : v.failed) EXPECT_TRUE(p.touching_at_start);
}

TEST(Verify, ParticlesAreVerticesOfNoBody) {
  const Model m = stacked(0.5);
  StepVerifier verifier(m.mesh);
  const Index first_particle = static_cast<Index>(m.mesh.x.size());
  std::vector<Vec3> x0 = m.mesh.x, x1 = m.mesh.x;
  x0.push_back(Vec3(0.1, 0.3, 0.6));  // above a's top face, off its triangles' edges
  x1.push_back(Vec3(0.1, 0.3, 0.4));  // through it
  Scene scene(m, x0, 1);
  Verification v = scene.verify(verifier, x1);
  ASSERT_EQ(v.failed.size(), 1u);
  EXPECT_EQ(v.failed[0].nodes[0], first_particle);
  EXPECT_EQ(v.failed[0].body_a, -1);
  EXPECT_FALSE(v.failed[0].edge_edge);
  x1.back() = Vec3(0.1, 0.3, 0.55);  // stops short
  v = scene.verify(verifier, x1);
  EXPECT_TRUE(v.failed.empty());
}

namespace {

// The failing pairs as comparable keys: (edge–edge, touching, the pair's four nodes).
std::set<std::array<Index, 6>> keys(const Verification& v) {
  std::set<std::array<Index, 6>> out;
  for (const FailedPair& p : v.failed)
    out.insert({p.edge_edge, p.touching_at_start, p.nodes[0], p.nodes[1], p.nodes[2], p.nodes[3]});
  return out;
}

// The pairs a brute-force search tests: every surface vertex (and particle) against every face
// of another body, every two edges of different bodies, whose boxes of x0 → x1 overlap.
long brute_force_pairs(const SurfacePrimitives& p, const State& st, const std::vector<Vec3>& x1) {
  const std::vector<Vec3>& x0 = st.x;
  const auto box = [&](std::initializer_list<Index> nodes) {
    std::vector<const Vec3*> pts;
    for (const Index n : nodes) pts.push_back(&x0[n]), pts.push_back(&x1[n]);
    Box b{*pts[0], *pts[0]};
    for (const Vec3* q : pts) b.lo = b.lo.cwiseMin(*q), b.hi = b.hi.cwiseMax(*q);
    return b;
  };
  long count = 0;
  std::vector<std::pair<Index, Index>> vertices;  // node, body
  for (std::size_t i = 0; i < p.nodes.size(); ++i) vertices.push_back({p.nodes[i], p.node_body[i]});
  for (Index i = 0; i < st.particle_count(); ++i) vertices.push_back({st.first_particle + i, -1});
  for (const auto& [n, body] : vertices)
    for (std::size_t f = 0; f < p.faces.size(); ++f) {
      const Face& k = p.faces[f];
      count += body != p.face_body[f] && boxes_overlap(box({n}), box({k[0], k[1], k[2]}));
    }
  for (std::size_t a = 0; a < p.edges.size(); ++a)
    for (std::size_t b = a + 1; b < p.edges.size(); ++b)
      count +=
          p.edge_body[a] != p.edge_body[b] &&
          boxes_overlap(box({p.edges[a][0], p.edges[a][1]}), box({p.edges[b][0], p.edges[b][1]}));
  return count;
}

}  // namespace

// The verifier's pairs are the detection's lists filtered by the step's boxes: as many as a
// brute-force search finds, for end positions within the lists' reach and beyond it (a search
// anew, counted); and a verification again after some nodes moved (within the reach and
// beyond, some through the other body) fails exactly the pairs a fresh verification fails.
TEST(Verify, ListsGiveTheBruteForcePairsAndAgainGivesAFreshVerificationsAnswer) {
  const Model m = stacked(0.02);
  // Two particles: one above b, one between the cubes.
  std::vector<Vec3> x0 = m.mesh.x;
  x0.push_back(Vec3(0.3, 0.4, 1.7));
  x0.push_back(Vec3(-0.2, 0.1, 0.51));
  Scene scene(m, x0, 2);
  const double reach = scene.candidates->reach();
  ASSERT_GT(reach, 0.0);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  StepVerifier again(m.mesh);
  long searches = 0, failing = 0, checked_again = 0, rounds = 0;
  for (const double down : {0.0, 0.01, 0.05, 0.3}) {
    std::vector<Vec3> x1 = moved(m, Vec3(0.01, -0.02, -down));
    x1.push_back(x0[x0.size() - 2] + Vec3(0, 0, -down));
    x1.push_back(x0.back() + Vec3(0.05, 0, -0.05));
    Verification v = scene.verify(again, x1);
    searches += v.searches;
    EXPECT_EQ(v.pairs_checked, brute_force_pairs(scene.candidates->primitives(), scene.st, x1))
        << down;
    for (int round = 0; round < 6; ++round) {
      // Some nodes moved: a few by a tenth of the reach, one in three rounds past it.
      std::vector<Index> changed;
      for (Index n = 0; n < static_cast<Index>(x1.size()); ++n)
        if (rng() % 7 == 0) {
          const double step = (round % 3 == 2 && rng() % 4 == 0) ? 3.0 * reach : 0.1 * reach;
          x1[n] += step * Vec3(unit(rng), unit(rng), unit(rng));
          changed.push_back(n);
        }
      v = again.verify_again(scene.st, x1, *scene.candidates, changed);
      searches += v.searches;
      StepVerifier fresh(m.mesh);
      Scene other(m, x0, 2);
      const Verification w = other.verify(fresh, x1);
      EXPECT_EQ(keys(v), keys(w)) << down << " " << round;
      EXPECT_LE(v.pairs_checked, w.pairs_checked + static_cast<long>(w.failed.size()));
      failing += static_cast<long>(w.failed.size());
      checked_again += v.pairs_checked;
      ++rounds;
    }
  }
  EXPECT_GT(failing, 20);  // through the other body: pairs fail
  EXPECT_GT(searches, 1);  // moves past the reach searched anew
  EXPECT_GT(checked_again, rounds);
}
