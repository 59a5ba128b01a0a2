// The detection's one broadphase (broadphase/contact_candidates.hpp): the pairs it lists for
// the bodies and for the particles are exactly those a brute-force test of the boxes gives, and
// its binding lists, kept while nothing has moved past the reach, hold every pair a fresh
// search would find.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <utility>
#include <vector>

#include "tetcontact/broadphase/contact_candidates.hpp"
#include "tetcontact/fracture/particles.hpp"
#include "tetcontact/mesh/generators.hpp"

using namespace tc;

namespace {

using Pairs = std::set<std::pair<Index, Index>>;

// Two boxes of 2 × 2 × 2 hexes, b 0.05 above a and shifted, and particles about their faces and
// each other; every node moves by a small rotation over the step.
struct Scene {
  Mesh mesh;
  std::vector<Surface> surfaces;
  State st;
  Index b_first = 0;
  Scene() {
    add_body(mesh, "a", make_box(Vec3(1, 1, 1), {2, 2, 2}, HexSplit::six));
    b_first = static_cast<Index>(mesh.x.size());
    TetMesh b = make_box(Vec3(1, 1, 1), {2, 2, 2}, HexSplit::six);
    for (Vec3& p : b.x) p += Vec3(0.3, 0.2, 1.05);
    add_body(mesh, "b", b);
    surfaces = build_surfaces(mesh);
    st.x = mesh.x;
    st.m.assign(mesh.x.size(), 1.0);
    st.v.assign(mesh.x.size(), Vec3::Zero());
    st.first_particle = static_cast<Index>(mesh.x.size());
    const Vec3 at[] = {{0.0, 0.0, 0.56}, {0.52, 0.1, 0.0}, {0.55, 0.1, 0.0}, {0.3, 0.2, 0.5},
                       {0.0, -0.6, 0.0}, {2.0, 2.0, 2.0},  {0.1, 0.3, 1.3}};
    for (const Vec3& p : at) add_particle(st, p, Vec3::Zero(), 1e-3, 0.03, 0.0, 0);
    move(0.0);
  }
  // x* = x turned by `angle` about z, and b sunk by 3 × angle (into a from 0.017 on).
  void move(double angle) {
    st.x_star = st.x;
    const double c = std::cos(angle), s = std::sin(angle);
    for (std::size_t i = 0; i < st.x_star.size(); ++i) {
      const Vec3 p = st.x_star[i];
      const double sink =
          static_cast<Index>(i) >= b_first && static_cast<Index>(i) < first_particle() ? 3.0 * angle
                                                                                       : 0.0;
      st.x_star[i] = Vec3(c * p.x() - s * p.y(), s * p.x() + c * p.y(), p.z() - sink);
    }
  }
  Index first_particle() const { return st.first_particle; }
};

Box particle_box(const State& st, Index i, double margin) {
  const Index p = st.first_particle + i;
  return swept_box({&st.x[p], &st.x_star[p]}, st.particle_radius[i] + margin);
}

// The brute-force pairs of the boxes the narrow phases test, with every box enlarged by `reach`:
// a face's layer box for node–face contact, its path for particles.
struct Oracle {
  Pairs node_face, edge_edge, particle_face, particle_particle;
};

Oracle brute_force(const Scene& s, const SurfacePrimitives& p, const CandidateSettings& c,
                   double reach) {
  const std::vector<Vec3>&x0 = s.st.x, &x1 = s.st.x_star;
  const double margin = c.margin + reach;
  std::vector<Box> face(p.faces.size());
  for (std::size_t f = 0; f < p.faces.size(); ++f)
    face[f] = layer_box(p.faces[f], s.mesh.tets[p.face_tet[f]], x0, x1, c.rim, margin);
  Oracle o;
  for (std::size_t i = 0; i < p.nodes.size(); ++i) {
    const Box b = swept_box({&x0[p.nodes[i]], &x1[p.nodes[i]]}, margin);
    for (std::size_t f = 0; f < face.size(); ++f)
      if (p.node_body[i] != p.face_body[f] && boxes_overlap(b, face[f]))
        o.node_face.insert({static_cast<Index>(i), static_cast<Index>(f)});
  }
  for (std::size_t a = 0; a < p.edges.size(); ++a)
    for (std::size_t b = a + 1; b < p.edges.size(); ++b) {
      const Edge &e = p.edges[a], &g = p.edges[b];
      if (p.edge_body[a] != p.edge_body[b] &&
          boxes_overlap(swept_box({&x0[e[0]], &x0[e[1]], &x1[e[0]], &x1[e[1]]}, margin),
                        swept_box({&x0[g[0]], &x0[g[1]], &x1[g[0]], &x1[g[1]]}, margin)))
        o.edge_edge.insert({static_cast<Index>(a), static_cast<Index>(b)});
    }
  const Index n = s.st.particle_count();
  for (Index i = 0; i < n; ++i) {
    for (std::size_t f = 0; f < face.size(); ++f) {
      const Face& k = p.faces[f];
      const Box path =
          swept_box({&x0[k[0]], &x0[k[1]], &x0[k[2]], &x1[k[0]], &x1[k[1]], &x1[k[2]]}, reach);
      if (boxes_overlap(particle_box(s.st, i, reach), path))
        o.particle_face.insert({i, static_cast<Index>(f)});
    }
    for (Index j = i + 1; j < n; ++j)
      if (boxes_overlap(particle_box(s.st, i, reach), particle_box(s.st, j, reach)))
        o.particle_particle.insert({i, j});
  }
  return o;
}

Pairs as_set(const std::vector<std::pair<Index, Index>>& v) {
  EXPECT_TRUE(std::is_sorted(v.begin(), v.end()));
  return Pairs(v.begin(), v.end());
}

CandidateSettings both(const std::string& method, bool binding_lists) {
  CandidateSettings c;
  c.broadphase = method;
  c.binding_lists = binding_lists;
  c.edges = true;
  c.particles = true;
  c.margin = 1e-3;
  c.rim = 1e-3;
  return c;
}

}  // namespace

// Without binding lists, the update gives the bodies' node–face and edge–edge pairs and the
// particles' pairs with faces (their own body's too) and with each other, and nothing else: no
// pair within a body, none of a particle and a surface edge.
TEST(ContactCandidates, TheUpdateListsWhatTheBoxesOfEachNarrowPhaseOverlap) {
  for (const char* method : {"brute_force", "sweep", "grid", "fcl_tree", "fcl_sap"}) {
    SCOPED_TRACE(method);
    Scene s;
    s.move(0.02);
    const CandidateSettings c = both(method, false);
    ContactCandidates cand(s.mesh, s.surfaces, c);
    EXPECT_TRUE(cand.update(s.st).rebuilt);
    const Oracle o = brute_force(s, cand.primitives(), c, 0.0);
    EXPECT_EQ(as_set(cand.bodies().node_face), o.node_face);
    EXPECT_EQ(as_set(cand.bodies().edge_edge), o.edge_edge);
    EXPECT_EQ(as_set(cand.particles().node_face), o.particle_face);
    EXPECT_EQ(as_set(cand.particles().edge_edge), o.particle_particle);
    // The scene has pairs of every kind, the particles' with both bodies.
    EXPECT_GT(o.node_face.size(), 10u);
    EXPECT_GT(o.edge_edge.size(), 10u);
    EXPECT_EQ(o.particle_particle.size(), 1u);  // the two particles 0.03 apart
    std::set<Index> bodies;
    for (const auto& [i, f] : o.particle_face) bodies.insert(cand.primitives().face_body[f]);
    EXPECT_EQ(bodies.size(), 2u);
    EXPECT_EQ(cand.bodies().faces, listed_faces(cand.bodies().node_face));
  }
}

// With binding lists: kept while every surface node and particle stays within the reach, and
// then every pair the boxes of the step give is listed; once only a particle has moved past it,
// the particles' lists are found anew and the bodies' kept.
TEST(ContactCandidates, BindingListsHoldEveryPairOfTheStepUntilSomethingLeavesTheReach) {
  Scene s;
  const CandidateSettings c = both("grid", true);
  ContactCandidates cand(s.mesh, s.surfaces, c);
  EXPECT_GT(cand.reach(), 0.0);
  EXPECT_TRUE(cand.update(s.st).rebuilt);
  const auto contains = [](const Pairs& big, const Pairs& small) {
    return std::includes(big.begin(), big.end(), small.begin(), small.end());
  };
  int kept = 0;
  for (int k = 1; k <= 40; ++k) {
    s.move(0.005 * k);  // the turn grows: the lists run out after a while
    const bool rebuilt = cand.update(s.st).rebuilt;
    kept += !rebuilt;
    const Oracle o = brute_force(s, cand.primitives(), c, 0.0);
    ASSERT_TRUE(contains(as_set(cand.bodies().node_face), o.node_face)) << "step " << k;
    ASSERT_TRUE(contains(as_set(cand.bodies().edge_edge), o.edge_edge)) << "step " << k;
    ASSERT_TRUE(contains(as_set(cand.particles().node_face), o.particle_face)) << "step " << k;
    ASSERT_TRUE(contains(as_set(cand.particles().edge_edge), o.particle_particle)) << "step " << k;
  }
  EXPECT_GT(kept, 5);
  EXPECT_LT(kept, 40);
  // A particle moved past the reach: the particles' lists are found anew, the bodies' kept.
  s.move(0.0);
  EXPECT_FALSE(cand.update(s.st).rebuilt);
  const CandidateLists bodies = cand.bodies();
  s.st.x[s.st.first_particle] += Vec3(2.0 * cand.reach(), 0, 0);
  s.st.x_star[s.st.first_particle] += Vec3(2.0 * cand.reach(), 0, 0);
  EXPECT_TRUE(cand.update(s.st).rebuilt);
  EXPECT_EQ(cand.bodies().node_face, bodies.node_face);
  EXPECT_EQ(cand.bodies().edge_edge, bodies.edge_edge);
  const Oracle o = brute_force(s, cand.primitives(), c, 0.0);
  EXPECT_TRUE(contains(as_set(cand.particles().node_face), o.particle_face));
  EXPECT_TRUE(contains(as_set(cand.particles().edge_edge), o.particle_particle));
}

// Cells turned into particles: the lists that hold are updated, not found anew. The pairs of
// the primitives that stay keep their place under their new numbers; the faces, edges and nodes
// a removal exposes, the new particle and the joined one (grown and moved) are paired with the
// rest. At every later step the lists hold every pair the boxes give, as after a search, and
// the first steps search nothing.
TEST(ContactCandidates, ListsUpdatedAcrossAConversionHoldEveryPairAFreshSearchFinds) {
  Scene s;
  const CandidateSettings c = both("grid", true);
  ContactCandidates cand(s.mesh, s.surfaces, c);
  EXPECT_TRUE(cand.update(s.st).rebuilt);
  // Body b (x in [−0.2, 0.8], z in [0.55, 1.55]) loses its lower hexes at low x, exposing their
  // neighbours' faces at x = 0.3 and z = 1.05 and its middle node; a new particle between them
  // and a's top (z = 0.5), and particle 5 (far out) joined by a cell there too.
  const TetNeighbours neighbours = tet_neighbours(s.mesh);
  std::vector<char> removed(s.mesh.tets.size(), 0);
  int lost = 0;
  for (std::size_t t = 0; t < s.mesh.tets.size(); ++t) {
    if (s.mesh.tet_body[t] != 1) continue;
    removed[t] = 1;
    for (const Index n : s.mesh.tets[t])
      if (s.mesh.x[n].z() > 1.1 || s.mesh.x[n].x() > 0.35) removed[t] = 0;
    lost += removed[t];
  }
  ASSERT_EQ(lost, 12);
  const std::vector<Surface> after = build_surfaces(s.mesh, neighbours, removed);
  add_particle(s.st, Vec3(0.1, 0.1, 0.52), Vec3::Zero(), 1e-3, 0.03, 0.0, 0);
  const Index joined = s.st.first_particle + 5;
  s.st.x[joined] = Vec3(-0.3, -0.2, 0.53);
  s.st.particle_radius[5] = 0.04;
  s.move(0.0);
  const long version = cand.version();
  cand.surfaces_changed(after, s.st);
  EXPECT_GT(cand.version(), version);
  const SurfacePrimitives fresh = surface_primitives(after, true);
  ASSERT_EQ(cand.primitives().faces, fresh.faces);
  ASSERT_EQ(cand.primitives().edges, fresh.edges);

  const auto contains = [](const Pairs& big, const Pairs& small) {
    return std::includes(big.begin(), big.end(), small.begin(), small.end());
  };
  // Pairs the update had to add: of an exposed face, of the new particle, of the joined one.
  Pairs exposed_pairs, new_particle_pairs, joined_pairs;
  int kept = 0;
  for (int k = 1; k <= 30; ++k) {
    s.move(0.002 * k);
    const bool rebuilt = cand.update(s.st).rebuilt;
    if (!rebuilt && kept == k - 1) ++kept;  // the run of steps kept from the conversion on
    const Oracle o = brute_force(s, cand.primitives(), c, 0.0);
    for (const char* part : {"bodies", "particles"}) {
      const CandidateLists& l = std::string(part) == "bodies" ? cand.bodies() : cand.particles();
      EXPECT_EQ(as_set(l.node_face).size(), l.node_face.size()) << part << ": a pair twice";
      EXPECT_EQ(as_set(l.edge_edge).size(), l.edge_edge.size()) << part << ": a pair twice";
      EXPECT_EQ(l.faces, listed_faces(l.node_face));
    }
    ASSERT_TRUE(contains(as_set(cand.bodies().node_face), o.node_face)) << "step " << k;
    ASSERT_TRUE(contains(as_set(cand.bodies().edge_edge), o.edge_edge)) << "step " << k;
    ASSERT_TRUE(contains(as_set(cand.particles().node_face), o.particle_face)) << "step " << k;
    ASSERT_TRUE(contains(as_set(cand.particles().edge_edge), o.particle_particle)) << "step " << k;
    for (const auto& [n, f] : o.node_face) {
      const Index tet = cand.primitives().face_tet[f];
      bool was = false;
      for (const Surface& surf : s.surfaces)
        for (std::size_t g = 0; g < surf.faces.size(); ++g)
          was = was || (surf.face_tet[g] == tet && surf.faces[g] == cand.primitives().faces[f]);
      if (!was) exposed_pairs.insert({n, f});
    }
    for (const auto& [i, f] : o.particle_face) {
      if (i == 7) new_particle_pairs.insert({i, f});
      if (i == 5) joined_pairs.insert({i, f});
    }
    for (const auto& [i, j] : o.particle_particle)
      if (i == 5 || j == 5 || i == 7 || j == 7) joined_pairs.insert({i, j});
  }
  EXPECT_GT(kept, 3);
  EXPECT_GT(exposed_pairs.size(), 0u);
  EXPECT_GT(new_particle_pairs.size(), 0u);
  EXPECT_GT(joined_pairs.size(), 0u);
}
