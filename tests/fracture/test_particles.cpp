// Destroyed boundary cells turned into particles: the conversion's conservation, the surfaces it
// exposes (against surfaces built from scratch without those cells), and particle contact
// (no tunnelling through a plate one cell thick, the exact outcome of a head-on collision).
#include <gtest/gtest.h>

#include <cmath>

#include "../solver/solver_fixture.hpp"
#include "tetcontact/fracture/particles.hpp"
#include "tetcontact/solver/integrator.hpp"
#include "tetcontact/solver/simulation.hpp"

using namespace tc;

namespace {

struct Totals {
  double mass = 0, energy = 0;
  Vec3 momentum = Vec3::Zero();
};

// Mass, momentum and kinetic + internal energy of the nodes, cells and particles, with the
// committed velocities (what the conversion carries).
Totals totals(const State& st) {
  Totals t;
  for (std::size_t i = 0; i < st.x.size(); ++i) {
    t.mass += st.m[i];
    t.momentum += st.m[i] * st.v[i];
    t.energy += 0.5 * st.m[i] * st.v[i].squaredNorm();
  }
  for (double e : st.e_int) t.energy += e;
  for (double e : st.particle_energy) t.energy += e;
  return t;
}

// Surfaces of the mesh with `removed` tets dropped, built from scratch (the oracle).
std::vector<Surface> surfaces_without(const Mesh& mesh, const std::vector<char>& removed) {
  Mesh m = mesh;
  m.tets.clear();
  m.tet_body.clear();
  for (BodyRange& b : m.bodies) {
    const Index begin = static_cast<Index>(m.tets.size());
    for (Index t = b.tet_begin; t < b.tet_end; ++t)
      if (!removed[t]) m.tets.push_back(mesh.tets[t]), m.tet_body.push_back(mesh.tet_body[t]);
    b.tet_begin = begin;
    b.tet_end = static_cast<Index>(m.tets.size());
  }
  return build_surfaces(m);
}

}  // namespace

TEST(Fragmentation, ConversionConservesMassMomentumEnergyAndExposesFaces) {
  Model model =
      test::single_body_model(make_box(Vec3(1, 1, 1), {3, 3, 3}, HexSplit::six), test::aluminium());
  State st = initial_state(model);
  for (std::size_t i = 0; i < st.x.size(); ++i)  // a velocity field with spread in every cell
    st.v[i] = Vec3(std::sin(3.0 * i), std::cos(5.0 * i), 0.5 - std::sin(7.0 * i));
  for (double& e : st.e_int) e = 2.0;
  const Totals before = totals(st);

  // Destroy one corner cell (on the boundary) and one cell at the centre (interior).
  const TetNeighbours nb = tet_neighbours(model.mesh);
  Index boundary = -1, interior = -1;
  for (Index t = 0; t < model.mesh.tet_count(); ++t) {
    const bool on_boundary = std::count(nb[t].begin(), nb[t].end(), -1) > 0;
    if (on_boundary && boundary < 0) boundary = t;
    const Vec3 c = 0.25 * (st.x[model.mesh.tets[t][0]] + st.x[model.mesh.tets[t][1]] +
                           st.x[model.mesh.tets[t][2]] + st.x[model.mesh.tets[t][3]]);
    if (!on_boundary && c.norm() < 0.2 && interior < 0) interior = t;
  }
  ASSERT_GE(boundary, 0);
  ASSERT_GE(interior, 0);
  st.damage[boundary] = st.damage[interior] = Damage::destroyed;

  Fragmentation frag(model.mesh);
  EXPECT_EQ(frag.convert(model.mesh, model.materials, st), 1);  // the interior one stays
  EXPECT_EQ(st.damage[boundary], Damage::particle);
  EXPECT_EQ(st.damage[interior], Damage::destroyed);
  ASSERT_EQ(st.particle_count(), 1);
  const Index p = st.first_particle;
  EXPECT_DOUBLE_EQ(st.m[p], 2700.0 * st.vol0[boundary]);
  // The particle sits at the centre of the cell's inscribed sphere: 4 faces at distance r.
  const Tet& k = model.mesh.tets[boundary];
  for (const auto& lf : k_tet_faces) {
    const Face f{k[lf[0]], k[lf[1]], k[lf[2]]};
    EXPECT_NEAR(face_normal(f, st.x).dot(st.x[f[0]] - st.x[p]), st.particle_radius[0], 1e-14);
  }

  const Totals after = totals(st);
  EXPECT_NEAR(after.mass, before.mass, 1e-15 * before.mass);
  EXPECT_NEAR((after.momentum - before.momentum).norm(), 0.0, 1e-14 * before.mass);
  EXPECT_NEAR(after.energy, before.energy, 1e-13 * before.energy);
  EXPECT_LT(frag.ledger().momentum_error, 1e-15);
  EXPECT_GT(frag.ledger().kinetic_spread, 0.0);

  std::vector<char> removed(model.mesh.tets.size(), 0);
  removed[boundary] = 1;
  const auto expect_same = [&](const std::vector<Surface>& got) {
    const std::vector<Surface> want = surfaces_without(model.mesh, removed);
    ASSERT_EQ(got.size(), want.size());
    EXPECT_EQ(got[0].faces, want[0].faces);
    EXPECT_EQ(got[0].edges, want[0].edges);
    EXPECT_EQ(got[0].nodes, want[0].nodes);
  };
  expect_same(frag.surfaces(model.mesh));

  // Destroy every cell: they convert a layer per call, from the outside in, the surfaces
  // following; the interior cell goes only once its neighbours have.
  for (Damage& d : st.damage)
    if (d == Damage::intact) d = Damage::destroyed;
  int calls = 0;
  while (frag.convert(model.mesh, model.materials, st) > 0) {
    ++calls;
    for (Index t = 0; t < model.mesh.tet_count(); ++t)
      removed[t] = st.damage[t] == Damage::particle;
    expect_same(frag.surfaces(model.mesh));
    if (calls == 1) {
      EXPECT_EQ(st.damage[interior], Damage::destroyed);
    }
  }
  EXPECT_GE(calls, 2);
  EXPECT_EQ(st.particle_count(), model.mesh.tet_count());
  for (Index n = 0; n < st.first_particle; ++n) EXPECT_EQ(st.m[n], 0.0);
  const Totals end = totals(st);
  EXPECT_NEAR(end.mass, before.mass, 1e-14 * before.mass);  // sums of 162 terms
  EXPECT_NEAR((end.momentum - before.momentum).norm(), 0.0, 1e-14 * before.mass);
  EXPECT_NEAR(end.energy, before.energy, 1e-13 * before.energy);
}

TEST(Fragmentation, NodeLeftWithoutCellsKeepsNoMass) {
  // A lone tet destroyed: its four nodes lose all their mass to the particle.
  TetMesh one;
  one.x = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  one.tets = {{0, 1, 2, 3}};
  Model model = test::single_body_model(one, test::aluminium());
  State st = initial_state(model);
  for (Vec3& v : st.v) v = Vec3(1, 2, 3);
  st.damage[0] = Damage::destroyed;
  Fragmentation frag(model.mesh);
  ASSERT_EQ(frag.convert(model.mesh, model.materials, st), 1);
  for (Index n = 0; n < 4; ++n) {
    EXPECT_EQ(st.m[n], 0.0);
    EXPECT_EQ(st.v[n], Vec3::Zero());
  }
  EXPECT_TRUE(frag.surfaces(model.mesh)[0].faces.empty());
  // The predictor leaves a massless node alone (no 0/0).
  st.dt = 1e-6;
  predict(st, {});
  for (const Vec3& v : st.v_star) EXPECT_TRUE(v.allFinite());
  EXPECT_EQ(st.v_star[4], Vec3(1, 2, 3));  // the particle flies on
}

namespace {

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
    ParticleContact contact("brute_force");
    std::vector<ContactPoint> cs = contact.detect(model.surfaces, model.mesh, st);
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
  ParticleContact contact("sweep");
  std::vector<ContactPoint> cs = contact.detect({}, Mesh{}, st);
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

TEST(Fragmentation, ErodedInteriorCellLeavesAVoidInTheSurfaces) {
  Model model =
      test::single_body_model(make_box(Vec3(1, 1, 1), {3, 3, 3}, HexSplit::six), test::aluminium());
  State st = initial_state(model);
  const TetNeighbours nb = tet_neighbours(model.mesh);
  Index interior = -1;
  for (Index t = 0; t < model.mesh.tet_count() && interior < 0; ++t)
    if (std::count(nb[t].begin(), nb[t].end(), -1) == 0) interior = t;
  ASSERT_GE(interior, 0);
  const Totals before = totals(st);
  Fragmentation frag(model.mesh);
  frag.erode({interior, interior});  // listed twice: converted once
  EXPECT_EQ(frag.convert(model.mesh, model.materials, st), 1);
  EXPECT_EQ(frag.ledger().eroded, 1);
  EXPECT_EQ(st.damage[interior], Damage::particle);
  std::vector<char> removed(model.mesh.tets.size(), 0);
  removed[interior] = 1;
  const std::vector<Surface> got = frag.surfaces(model.mesh),
                             want = surfaces_without(model.mesh, removed);
  EXPECT_EQ(got[0].faces, want[0].faces);
  EXPECT_EQ(got[0].faces.size(), model.surfaces[0].faces.size() + 4);  // the void's four faces
  EXPECT_NEAR(totals(st).mass, before.mass, 1e-14 * before.mass);
  EXPECT_EQ(frag.convert(model.mesh, model.materials, st), 0);  // nothing more to do
}

// Binding lists for particle contact: over 300 steps of a cloud of 200 particles falling onto a
// plate at about 50 m/s (5 µm a step against a reach of about 55 µm), the lists (built with
// boxes enlarged by the mean radius, kept while nothing has moved that far) give exactly the
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
  ParticleContact lists("grid", true), fresh("grid", false);
  const int steps = 300;
  long contacts = 0, moved = 0;
  for (int k = 0; k < steps; ++k) {
    st.dt = 1e-7;
    predict(st, {});
    std::vector<ContactPoint> a = lists.detect(model.surfaces, model.mesh, st);
    const std::vector<ContactPoint> b = fresh.detect(model.surfaces, model.mesh, st);
    ASSERT_EQ(a.size(), b.size()) << "step " << k;
    for (std::size_t c = 0; c < a.size(); ++c) {
      ASSERT_EQ(a[c].a_nodes, b[c].a_nodes) << "step " << k << ", contact " << c;
      ASSERT_EQ(a[c].b_nodes, b[c].b_nodes);
      ASSERT_EQ(a[c].b_w, b[c].b_w);
      ASSERT_EQ(a[c].normal, b[c].normal);
      ASSERT_EQ(a[c].gap, b[c].gap);
    }
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
  EXPECT_EQ(fresh.broadphase_runs(), steps);
  EXPECT_GT(lists.broadphase_runs(), 1);
  EXPECT_LT(lists.broadphase_runs(), steps / 3);
  RecordProperty("list_builds", std::to_string(lists.broadphase_runs()));
  RecordProperty("moved", std::to_string(moved));
}
