// Destroyed boundary cells turned into particles: the conversion's conservation and the surfaces
// it exposes (against surfaces built from scratch without those cells). Particle contact:
// tests/narrowphase/test_particle_contact.cpp.
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
