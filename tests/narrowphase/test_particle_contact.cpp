// Particle contact (narrowphase/particle_contact.hpp): no tunnelling through a plate one cell
// thick, the exact outcome of a head-on collision, and binding lists that give a fresh search's
// contacts.
#include <gtest/gtest.h>

#include <cmath>

#include "../solver/solver_fixture.hpp"
#include "same_contact_points.hpp"
#include "tetcontact/fracture/particles.hpp"
#include "tetcontact/narrowphase/particle_contact.hpp"
#include "tetcontact/solver/integrator.hpp"
#include "tetcontact/solver/simulation.hpp"

using namespace tc;

namespace {

// The detection's broadphase for particles alone (no contact between bodies).
CandidateSettings particles_only(const std::string& method, bool binding_lists) {
  return {.broadphase = method, .binding_lists = binding_lists, .bodies = false, .particles = true};
}

// A plate one cell thick (0.5 mm, top face at z = 0) and a particle above it.
struct PlateAndParticle {
  Model model;
  State st;
  PlateAndParticle(double height, const Vec3& velocity) {
    TetMesh plate = make_box(Vec3(4e-3, 4e-3, 0.5e-3), {4, 4, 1}, HexSplit::six);
    for (Vec3& x : plate.x) x.z() -= 0.25e-3;
    model = test::single_body_model(plate, test::aluminium());
    st = initial_state(model);
    add_particle(st, Vec3(0.1e-3, 0.2e-3, height), velocity, 1e-6, 0.1e-3, 0.0, 0);
  }
  // One step of corrections with the given passes: the particle's contacts with the faces.
  void correct(double tau, int passes) {
    st.dt = tau;
    predict(st, {});
    ContactCandidates candidates(model.mesh, model.surfaces, particles_only("brute_force", true));
    candidates.update(st);
    ParticleContact contact;
    std::vector<ContactPoint> cs = contact.detect(model.mesh, st, candidates);
    for (int p = 0; p < passes; ++p)
      for (ContactPoint& c : cs) apply_contact(c, st, tau, st.contact_impulse);
  }
};

}  // namespace

TEST(ParticleContact, NoTunnellingThroughAPlateOneCellThick) {
  // 10 km/s down from 1 mm above: unchecked, one step of 1 µs would carry it 10 mm, through
  // the plate and out the other side. The contact lets it close the gap and no more.
  PlateAndParticle s(1.0e-3, Vec3(0, 0, -1e4));
  const Index p = s.st.first_particle;
  Vec3 momentum = Vec3::Zero();
  for (std::size_t i = 0; i < s.st.x.size(); ++i) momentum += s.st.m[i] * s.st.v[i];
  s.correct(1e-6, 3);
  Vec3 after = Vec3::Zero();
  for (std::size_t i = 0; i < s.st.x.size(); ++i) after += s.st.m[i] * s.st.v_star[i];
  EXPECT_NEAR((after - momentum).norm(), 0.0, 1e-15 * momentum.norm());
  // At the end of the step the sphere touches the top face (z = 0 there, moved with its nodes).
  commit(s.st);
  double top = -1.0;
  for (Index n : s.model.surfaces[0].nodes)
    if (std::abs(s.model.mesh.x[n].z() - 0.25e-3) < 1e-12 &&
        (s.model.mesh.x[n].head<2>() - Vec3(0.1e-3, 0.2e-3, 0).head<2>()).norm() < 1.1e-3)
      top = std::max(top, s.st.x[n].z());
  EXPECT_GE(s.st.x[p].z() - 0.1e-3, top - 1e-12);
  EXPECT_LT(s.st.x[p].z(), 0.25e-3 + 0.1e-3 + 1e-6);  // and it did close the gap
}

TEST(ParticleContact, HeadOnParticlesMoveTogetherAfterwards) {
  // Two equal particles closing at 2 m/s, 1 µm apart: the contact is perfectly inelastic in
  // the normal direction (target: no approach), so both end at the mean velocity, touching.
  State st;
  st.first_particle = 0;
  add_particle(st, Vec3(0, 0, 0), Vec3(1, 0.5, 0), 2e-6, 1e-4, 0.0, 0);
  add_particle(st, Vec3(2e-4 + 1e-6, 0, 0), Vec3(-1, 0, 0), 2e-6, 1e-4, 0.0, 1);
  st.dt = 1e-5;
  predict(st, {});
  const Mesh none;
  ContactCandidates candidates(none, {}, particles_only("sweep", true));
  candidates.update(st);
  ParticleContact contact;
  std::vector<ContactPoint> cs = contact.detect(none, st, candidates);
  ASSERT_EQ(cs.size(), 1u);
  EXPECT_NEAR(cs[0].gap, 1e-6, 1e-18);
  apply_contact(cs[0], st, st.dt, st.contact_impulse);
  // Closing at 2 m/s over 10 µs would take 20 µm: the kernel allows 1 µm, i.e. 0.1 m/s.
  EXPECT_NEAR(st.v_star[0].x() - st.v_star[1].x(), 0.1, 1e-12);
  EXPECT_NEAR(st.v_star[0].x() + st.v_star[1].x(), 0.0, 1e-15);  // momentum
  EXPECT_EQ(st.v_star[0].y(), 0.5);                              // slip: no tangential change
  commit(st);
  EXPECT_NEAR(st.x[1].x() - st.x[0].x(), 2e-4, 1e-15);  // touching
}

// Binding lists for particle contact: over 300 steps of a cloud of 200 particles falling onto a
// plate at about 50 m/s (5 µm a step against a reach of 0.2 of the mean tet edge), the lists
// (built with boxes enlarged by the reach, kept while nothing has moved that far) give exactly the
// contacts, in the same order, and the same moves as a fresh broadphase every step, with far
// fewer broadphase runs. (Checked sensitive: lists kept until things moved 3 reaches fail at
// step 26.)
TEST(ParticleContact, BindingListsGiveTheContactsOfAFreshSearch) {
  TetMesh plate = make_box(Vec3(4e-3, 4e-3, 0.5e-3), {8, 8, 1}, HexSplit::six);
  Model model = test::single_body_model(plate, test::aluminium());
  State st = initial_state(model);
  unsigned seed = 12345;
  const auto uniform = [&](double lo, double hi) {
    seed = seed * 1664525u + 1013904223u;
    return lo + (hi - lo) * (seed >> 8) / double(1u << 24);
  };
  for (int i = 0; i < 200; ++i)
    add_particle(st,
                 Vec3(uniform(-1.5e-3, 1.5e-3), uniform(-1.5e-3, 1.5e-3), uniform(0.3e-3, 1.5e-3)),
                 Vec3(uniform(-5, 5), uniform(-5, 5), uniform(-55, -45)), 1e-7,
                 uniform(0.03e-3, 0.08e-3), 0.0, 0);
  ContactCandidates lists_pairs(model.mesh, model.surfaces, particles_only("grid", true)),
      fresh_pairs(model.mesh, model.surfaces, particles_only("grid", false));
  ParticleContact lists, fresh;
  const int steps = 300;
  long contacts = 0, moved = 0, list_builds = 0, fresh_builds = 0;
  for (int k = 0; k < steps; ++k) {
    st.dt = 1e-7;
    predict(st, {});
    list_builds += lists_pairs.update(st).rebuilt;
    fresh_builds += fresh_pairs.update(st).rebuilt;
    std::vector<ContactPoint> a = lists.detect(model.mesh, st, lists_pairs);
    const std::vector<ContactPoint> b = fresh.detect(model.mesh, st, fresh_pairs);
    ASSERT_TRUE(test::same_contact_points(a, b)) << "step " << k;
    ASSERT_EQ(lists.moves(), fresh.moves()) << "step " << k;
    contacts += static_cast<long>(a.size());
    for (const auto& [p, d] : lists.moves()) {
      st.x[p] += d;
      st.x_star[p] += d;
      ++moved;
    }
    for (ContactPoint& c : a) apply_contact(c, st, st.dt, st.contact_impulse);
    commit(st);
  }
  EXPECT_GT(contacts, 300);  // the scene has contacts to agree on
  EXPECT_EQ(fresh_builds, steps);
  EXPECT_GT(list_builds, 1);
  EXPECT_LT(list_builds, steps / 3);
  RecordProperty("list_builds", std::to_string(list_builds));
  RecordProperty("moved", std::to_string(moved));
}
