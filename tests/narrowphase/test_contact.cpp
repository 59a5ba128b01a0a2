// Contact detection between bodies (narrowphase/contact.hpp): a node that enters the other body
// through a face is a contact at the face with its outward normal, and the binding lists find
// at every step exactly the contacts a fresh broadphase search finds.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "same_contact_points.hpp"
#include "tetcontact/mesh/generators.hpp"
#include "tetcontact/mesh/surface.hpp"
#include "tetcontact/model/state.hpp"
#include "tetcontact/narrowphase/contact.hpp"

using namespace tc;

namespace {

// Body "a": a 1 × 1 × 1 box of 2 × 2 × 2 hexes; body "b": the same box of 3 × 3 × 3 hexes
// (faces that do not conform), turned about z and placed `gap` above a (a's top at z = ½).
struct Boxes {
  Mesh mesh;
  std::vector<Surface> surfaces;
  State st;
  Index b_first = 0;
  explicit Boxes(double gap) {
    add_body(mesh, "a", make_box(Vec3(1, 1, 1), {2, 2, 2}, HexSplit::six));
    b_first = static_cast<Index>(mesh.x.size());
    TetMesh b = make_box(Vec3(1, 1, 1), {3, 3, 3}, HexSplit::six);
    // Both boxes centred on the z axis (make_box: [−½, ½]³); b turned by 0.3 rad about it,
    // its bottom `gap` above a's top.
    const double c = std::cos(0.3), s = std::sin(0.3), lift = top_a() + gap + 0.5;
    for (Vec3& p : b.x) p = Vec3(c * p.x() - s * p.y(), s * p.x() + c * p.y(), p.z() + lift);
    add_body(mesh, "b", b);
    surfaces = build_surfaces(mesh);
    st.x = mesh.x;
    st.x_star = mesh.x;
    st.m.assign(mesh.x.size(), 1.0);
  }
  double top_a() const {
    double z = -1e300;
    for (Index i = 0; i < b_first; ++i) z = std::max(z, mesh.x[i].z());
    return z;
  }
};

}  // namespace

// b's nodes moved 0.07 down, from 0.02 above a's top to 0.05 into a. Detection is
// symmetric: each node of b that lands on a's top face, away from its rim, is a contact
// against that face with its outward normal +z (from the face to the node), and each node of
// a's top that b's bottom now covers is a contact against b's bottom face, normal −z; both at
// the gap at xⁿ (0.02), with the face's weights summing to 1.
TEST(ContactDetection, NodeEnteringAFaceIsAContactWithTheFacesNormal) {
  Boxes s(0.02);
  for (Index i = s.b_first; i < static_cast<Index>(s.st.x.size()); ++i)
    s.st.x_star[i] = s.st.x[i] - Vec3(0, 0, 0.07);
  ContactSettings settings;  // node–face contact alone
  settings.order = ContactSettings::Order::input;
  settings.edge_edge = false;
  ContactDetection contact(s.mesh, s.surfaces, settings, 0.0);
  ContactCandidates candidates(s.mesh, s.surfaces, candidate_settings(settings, false));
  EXPECT_TRUE(candidates.update(s.st).rebuilt);
  ContactStepStats stats;
  const std::vector<ContactPoint> found = contact.detect(s.st, candidates, stats);
  long b_on_a = 0, a_under_b = 0;
  for (const ContactPoint& c : found) {
    ASSERT_EQ(c.a_count, 1);
    ASSERT_EQ(c.b_count, 3);
    const bool node_of_b = c.a_nodes[0] >= s.b_first;
    double w = 0.0;
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(c.b_nodes[k] >= s.b_first, !node_of_b);  // a face of the other body
      w += c.b_w[k];
    }
    EXPECT_NEAR(w, 1.0, 1e-12);
    // Against a's top face (its nodes at z = 1) or b's bottom face (at 1.02): the face's
    // outward normal and the gap at xⁿ. (A node near the other body's rim may take a side
    // face, whose normal is horizontal.)
    const double face_z = node_of_b ? s.top_a() : s.mesh.x[s.b_first].z();
    bool flat = true;
    for (int k = 0; k < 3; ++k) flat = flat && s.mesh.x[c.b_nodes[k]].z() == face_z;
    if (flat) {
      ++(node_of_b ? b_on_a : a_under_b);
      EXPECT_NEAR((c.normal - Vec3(0, 0, node_of_b ? 1 : -1)).norm(), 0.0, 1e-12);
      EXPECT_NEAR(c.gap, 0.02, 1e-12);
    }
  }
  EXPECT_GE(b_on_a, 4);  // b's bottom has 16 nodes, a's top 9: most over the other face
  EXPECT_GE(a_under_b, 1);
  EXPECT_EQ(stats.contacts + stats.edge_contacts, static_cast<long>(found.size()));
}

// Binding lists (kept while the surface nodes stay within the reach) against a fresh search
// every step, over 200 steps of b sliding over a, sinking slowly and turning: the same contacts,
// in the same order, with the same weights, normals and gaps, bit for bit.
TEST(ContactDetection, BindingListsFindWhatAFreshSearchFinds) {
  Boxes s(0.01);
  ContactSettings on, off;  // node–face contact alone
  on.edge_edge = off.edge_edge = false;
  off.binding_lists = false;
  ContactDetection lists(s.mesh, s.surfaces, on, 0.0), fresh(s.mesh, s.surfaces, off, 0.0);
  ContactCandidates lists_pairs(s.mesh, s.surfaces, candidate_settings(on, false)),
      fresh_pairs(s.mesh, s.surfaces, candidate_settings(off, false));
  const double dt = 1e-3;
  long contacts = 0, rebuilds = 0;
  const int steps = 200;
  for (int k = 0; k < steps; ++k) {
    for (Index i = s.b_first; i < static_cast<Index>(s.st.x.size()); ++i) {
      const Vec3& r = s.st.x[i];
      const Vec3 v = Vec3(0.4, 0.1, -0.15) + Vec3(-r.y(), r.x(), 0.0) * 0.5;
      s.st.x_star[i] = s.st.x[i] + dt * v;
    }
    const CandidateStats a_update = lists_pairs.update(s.st);
    const CandidateStats b_update = fresh_pairs.update(s.st);
    ContactStepStats a_stats, b_stats;
    const std::vector<ContactPoint> a = lists.detect(s.st, lists_pairs, a_stats);
    const std::vector<ContactPoint> b = fresh.detect(s.st, fresh_pairs, b_stats);
    ASSERT_TRUE(test::same_contact_points(a, b)) << "step " << k;
    EXPECT_TRUE(b_update.rebuilt);
    contacts += static_cast<long>(a.size());
    rebuilds += a_update.rebuilt;
    s.st.x = s.st.x_star;
  }
  EXPECT_GT(contacts, 500);  // the scene has contacts to agree on
  EXPECT_GT(rebuilds, 1);    // the lists ran out and were found again
  EXPECT_LT(rebuilds, steps / 4);
}
