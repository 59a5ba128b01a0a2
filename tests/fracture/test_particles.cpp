// Destroyed boundary cells turned into particles: the conversion's conservation and the surfaces
// it exposes (against surfaces built from scratch without those cells), and cells that cohere
// joined into one particle (fracture.fragments: clusters). Particle contact:
// tests/narrowphase/test_particle_contact.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "../solver/solver_fixture.hpp"
#include "tetcontact/diagnostics/reference.hpp"
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
  std::vector<Surface> surfaces;
  frag.update(model.mesh, surfaces);
  expect_same(surfaces);

  // Destroy every cell: they convert a layer per call, from the outside in, the surfaces
  // following; the interior cell goes only once its neighbours have.
  for (Damage& d : st.damage)
    if (d == Damage::intact) d = Damage::destroyed;
  int calls = 0;
  while (frag.convert(model.mesh, model.materials, st) > 0) {
    ++calls;
    for (Index t = 0; t < model.mesh.tet_count(); ++t)
      removed[t] = st.damage[t] == Damage::particle;
    frag.update(model.mesh, surfaces);  // updated for the cells this call converted
    expect_same(surfaces);
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
  std::vector<Surface> surfaces;
  frag.update(model.mesh, surfaces);
  EXPECT_TRUE(surfaces[0].faces.empty());
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
  std::vector<Surface> got;
  frag.update(model.mesh, got);
  const std::vector<Surface> want = surfaces_without(model.mesh, removed);
  EXPECT_EQ(got[0].faces, want[0].faces);
  EXPECT_EQ(got[0].faces.size(), model.surfaces[0].faces.size() + 4);  // the void's four faces
  EXPECT_NEAR(totals(st).mass, before.mass, 1e-14 * before.mass);
  EXPECT_EQ(frag.convert(model.mesh, model.materials, st), 0);  // nothing more to do
}

namespace {

// Two tets sharing the face (1, 2, 3), both destroyed; node 4 (the second's apex) moves at w
// along x, so the cells' mean velocities differ by w / 4.
struct TwoCells {
  Model model;
  State st;
  TwoCells(double w, double spall_strength) {
    TetMesh two;
    two.x = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1), Vec3(1, 1, 1)};
    two.tets = {{0, 1, 2, 3}, {1, 2, 3, 4}};
    Material m = test::aluminium();
    m.spall_strength = spall_strength;
    model = test::single_body_model(two, m);
    st = initial_state(model);
    st.v[4] = Vec3(w, 0, 0);
    st.e_int = {1.0, 2.0};
    st.damage[0] = st.damage[1] = Damage::destroyed;
  }
};

}  // namespace

TEST(Fragmentation, CoheringCellsJoinOneParticleAsAnInelasticCollision) {
  const Material al = test::aluminium();
  const double spall = 1.2e9;
  const double v_c = 2.0 * spall / (al.density * al.bulk_sound_speed());  // 2σ*/(ρ0 c0)
  ASSERT_GT(v_c, 50.0);
  ASSERT_LT(v_c, 500.0);

  // Below the cohesion speed: one particle, of both cells.
  {
    TwoCells c(4.0 * 0.5 * v_c, spall);
    const Totals before = totals(c.st);
    Fragmentation frag(c.model.mesh, Fragments::clusters);
    ASSERT_EQ(frag.convert(c.model.mesh, c.model.materials, c.st), 2);
    ASSERT_EQ(c.st.particle_count(), 1);
    const Index p = c.st.first_particle;
    EXPECT_EQ(frag.particle_of(0), p);
    EXPECT_EQ(frag.particle_of(1), p);
    EXPECT_EQ(frag.ledger().particles, 2);
    EXPECT_EQ(frag.ledger().joined, 1);
    const double m0 = al.density * c.st.vol0[0], m1 = al.density * c.st.vol0[1];
    EXPECT_NEAR(c.st.m[p], m0 + m1, 1e-15 * (m0 + m1));
    // Momentum m1 · w/4 along x; the loss ½ m0 m1/(m0+m1) (w/4)².
    EXPECT_NEAR(c.st.v[p].x(), m1 * 0.5 * v_c / (m0 + m1), 1e-12 * v_c);
    EXPECT_NEAR(frag.ledger().cohesion_loss, 0.5 * m0 * m1 / (m0 + m1) * std::pow(0.5 * v_c, 2),
                1e-12 * frag.ledger().cohesion_loss);
    // The centre of mass of the two inscribed spheres' centres, the volume of both spheres.
    Fragmentation alone(c.model.mesh);
    TwoCells d(4.0 * 0.5 * v_c, 0.0);  // the same cells, each its own particle
    ASSERT_EQ(alone.convert(d.model.mesh, d.model.materials, d.st), 2);
    const Index q = d.st.first_particle;
    const Vec3 com = (m0 * d.st.x[q] + m1 * d.st.x[q + 1]) / (m0 + m1);
    EXPECT_NEAR((c.st.x[p] - com).norm(), 0.0, 1e-15);
    EXPECT_NEAR(std::pow(c.st.particle_radius[0], 3),
                std::pow(d.st.particle_radius[0], 3) + std::pow(d.st.particle_radius[1], 3), 1e-15);
    const Totals after = totals(c.st);
    EXPECT_NEAR(after.mass, before.mass, 1e-15 * before.mass);
    EXPECT_NEAR((after.momentum - before.momentum).norm(), 0.0, 1e-15 * before.momentum.norm());
    EXPECT_NEAR(after.energy, before.energy, 1e-14 * before.energy);
  }
  // Apart: the first cell's particle carried off beyond 2 (R + r) before the second converts.
  {
    TwoCells c(0.0, spall);
    c.st.damage[1] = Damage::intact;
    Fragmentation frag(c.model.mesh, Fragments::clusters);
    ASSERT_EQ(frag.convert(c.model.mesh, c.model.materials, c.st), 1);
    const Index p = c.st.first_particle;
    const double reach = 2.0 * 2.0 * c.st.particle_radius[0];  // 2 (R + r), r ≈ R here
    c.st.x[p] += Vec3(0, 0, -2.0 * reach);
    c.st.damage[1] = Damage::destroyed;
    ASSERT_EQ(frag.convert(c.model.mesh, c.model.materials, c.st), 1);
    EXPECT_EQ(c.st.particle_count(), 2);
    EXPECT_EQ(frag.ledger().joined, 0);
  }
  // Of another material: a particle per cell.
  {
    TwoCells c(0.0, spall);
    c.model.materials.push_back(c.model.materials[0]);
    c.st.tet_material[1] = 1;
    Fragmentation frag(c.model.mesh, Fragments::clusters);
    ASSERT_EQ(frag.convert(c.model.mesh, c.model.materials, c.st), 2);
    EXPECT_EQ(c.st.particle_count(), 2);
  }
  // Above it, or in a material that does not spall: a particle per cell.
  for (const auto& [w, strength] : {std::pair{4.0 * 2.0 * v_c, spall}, std::pair{0.0, 0.0}}) {
    TwoCells c(w, strength);
    const Totals before = totals(c.st);
    Fragmentation frag(c.model.mesh, Fragments::clusters);
    ASSERT_EQ(frag.convert(c.model.mesh, c.model.materials, c.st), 2);
    EXPECT_EQ(c.st.particle_count(), 2);
    EXPECT_EQ(frag.ledger().joined, 0);
    EXPECT_EQ(frag.ledger().cohesion_loss, 0.0);
    EXPECT_NEAR(totals(c.st).energy, before.energy, 1e-14 * before.energy);
  }
}

TEST(Fragmentation, ClustersHoldTheirCellsMassAndConserveAWholeBodysBreakUp) {
  // Every cell of a box destroyed, the nodes' velocities spread about a common drift by less
  // and by more than the cohesion speed: each particle is the mass of the cells it holds, they
  // are face-connected, and mass, momentum and energy are those of the cells.
  for (const double spread : {0.1, 10.0}) {
    Material m = test::aluminium();
    m.spall_strength = 1.2e9;
    const double v_c = 2.0 * m.spall_strength / (m.density * m.bulk_sound_speed());
    Model model = test::single_body_model(make_box(Vec3(1, 1, 1), {3, 3, 3}, HexSplit::six), m);
    State st = initial_state(model);
    for (std::size_t i = 0; i < st.x.size(); ++i)
      st.v[i] = Vec3(1000.0, 0, 0) + spread * v_c * Vec3(std::sin(3.0 * i), std::cos(5.0 * i), 0.0);
    for (Damage& d : st.damage) d = Damage::destroyed;
    const Totals before = totals(st);
    Fragmentation frag(model.mesh, Fragments::clusters);
    while (frag.convert(model.mesh, model.materials, st) > 0) {
    }
    const Index cells = model.mesh.tet_count();
    EXPECT_EQ(frag.ledger().particles, cells);
    EXPECT_EQ(st.particle_count() + frag.ledger().joined, cells);
    if (spread < 1.0) {
      EXPECT_LT(st.particle_count(), cells / 4);  // they cohere
    } else {
      EXPECT_GT(st.particle_count(), cells / 2);  // most part
    }

    // Brute force: each particle's members, their mass and their connection through faces.
    const TetNeighbours nb = tet_neighbours(model.mesh);
    std::vector<double> held(st.particle_count(), 0.0);
    for (Index t = 0; t < cells; ++t) {
      const Index p = frag.particle_of(t);
      ASSERT_GE(p, st.first_particle);
      held[p - st.first_particle] += m.density * st.vol0[t];
      if (st.particle_tet[p - st.first_particle] != t) {  // joined: a neighbour is in it too
        bool touches = false;
        for (Index o : nb[t]) touches = touches || (o >= 0 && frag.particle_of(o) == p);
        EXPECT_TRUE(touches) << "cell " << t;
      }
    }
    for (Index i = 0; i < st.particle_count(); ++i)
      EXPECT_NEAR(st.m[st.first_particle + i], held[i], 1e-14 * held[i]);
    const Totals after = totals(st);
    EXPECT_NEAR(after.mass, before.mass, 1e-14 * before.mass);
    EXPECT_NEAR((after.momentum - before.momentum).norm(), 0.0, 1e-14 * before.momentum.norm());
    EXPECT_NEAR(after.energy, before.energy, 1e-13 * before.energy);
  }
}

// On a symmetry plane (x = 0, which the first cell's face (0, 2, 3) lies on) a cell coheres with
// its own mirror image when they part slower than v_c, 2 |Ū_x| < v_c: its cluster spans the
// plane, and the largest fragment counts the whole, twice the model's part.
TEST(Fragmentation, AClusterCoheringWithItsMirrorImageSpansTheSymmetryPlane) {
  const double spall = 1.2e9;
  const Material al = test::aluminium();
  const double v_c = 2.0 * spall / (al.density * al.bulk_sound_speed());
  EXPECT_DOUBLE_EQ(cohesion_speed([&] {
                     Material m = al;
                     m.spall_strength = spall;
                     return m;
                   }()),
                   v_c);
  ReferenceSpec largest;
  largest.measure = ReferenceSpec::Measure::largest_fragment;
  largest.body = "body";
  largest.plane_point = Vec3(0, 0, -10);  // every particle beyond it
  largest.value = std::numeric_limits<double>::quiet_NaN();
  for (const double drift : {0.25 * v_c, 0.75 * v_c}) {
    TwoCells c(0.0, spall);
    c.model.mesh.symmetry = {SymmetryPlane{0, 0.0}};
    for (Vec3& v : c.st.v) v = Vec3(drift, 0, 0);
    Fragmentation frag(c.model.mesh, Fragments::clusters);
    ASSERT_EQ(frag.convert(c.model.mesh, c.model.materials, c.st), 2);
    ASSERT_EQ(c.st.particle_count(), 1);       // the two cells move together
    frag.update(c.model.mesh, c.st.surfaces);  // none left: nothing shields the particle
    const bool spans = 2.0 * drift < v_c;
    EXPECT_EQ(c.st.particle_planes[0], spans ? 1u : 0u) << drift;
    const std::vector<ReferenceResult> r = evaluate_references({largest}, c.model, c.st);
    ASSERT_EQ(r.size(), 1u);
    EXPECT_DOUBLE_EQ(r[0].measured, (spans ? 2.0 : 1.0) * c.st.m[c.st.first_particle]) << drift;
  }
  // Single cells never span: each image is a particle of its own.
  TwoCells c(0.0, spall);
  c.model.mesh.symmetry = {SymmetryPlane{0, 0.0}};
  Fragmentation frag(c.model.mesh);
  ASSERT_EQ(frag.convert(c.model.mesh, c.model.materials, c.st), 2);
  EXPECT_EQ(c.st.particle_planes, (std::vector<unsigned>{0u, 0u}));
}

// SPH debris (fracture.debris: sph): the particle a cell becomes carries the cell's material
// state as it stands (deviator, pressure, plastic strain, damage, temperature, sound speed,
// volume and so density), h = smoothing × V0^(1/3), and the conversion's mass, momentum and
// energy are as exact as a point mass's. A destroyed cell drawn out far beyond its volume becomes
// its material at the volume where its pressure at its energy is zero (no kick): with
// Mie–Grüneisen on its linear branch of expansion, with Tillotson by Newton's iteration; a hot
// Tillotson state (above E_cv) is a gas with no such volume and starts at twice V0. A compressed
// cell whose EOS reads more than its pressure (a cell crushed under the average nodal pressure)
// becomes its material at the larger volume where the EOS reads the cell's pressure; one whose
// EOS reads less keeps its volume.
static void particle_keeps_cells_state(const Material& al, double heat = 1e6) {
  Model model = test::single_body_model(make_box(Vec3(1, 1, 1), {3, 3, 3}, HexSplit::six), al);
  State st = initial_state(model);
  for (std::size_t i = 0; i < st.x.size(); ++i)
    st.v[i] = Vec3(std::sin(3.0 * i), std::cos(5.0 * i), 0.5 - std::sin(7.0 * i));
  const TetNeighbours nb = tet_neighbours(model.mesh);
  std::vector<Index> boundary;
  for (Index t = 0; t < model.mesh.tet_count(); ++t)
    if (std::count(nb[t].begin(), nb[t].end(), -1) > 0 && boundary.size() < 4)
      boundary.push_back(t);
  ASSERT_EQ(boundary.size(), 4u);
  // An eroded cell, compressed and strained, whose EOS reads far more than its 3 GPa; a
  // destroyed one drawn out to 50 times its volume; an eroded one whose EOS reads 1 GPa less
  // than its pressure; an eroded one so hot (20 MJ/kg) that its EOS reads more than its 3 GPa
  // even at twice its reference volume.
  const Index eroded = boundary[0], drawn = boundary[1], kept = boundary[2], hot = boundary[3];
  st.vol[eroded] = 0.8 * st.vol0[eroded];
  st.s[eroded] = Sym6{1e8, -0.5e8, -0.5e8, 2e7, 0, -1e7};
  st.p[eroded] = 3e9;
  st.eps_p[eroded] = 0.4;
  st.temperature[eroded] = 500.0;
  st.sound2[eroded] = 4e7;
  st.e_int[eroded] = 2.0;
  st.damage[drawn] = Damage::destroyed;
  st.vol[drawn] = 50.0 * st.vol0[drawn];
  st.e_int[drawn] = heat * al.density * st.vol0[drawn];  // 1 MJ/kg of heat by default
  st.vol[kept] = 0.9 * st.vol0[kept];
  st.e_int[kept] = 2.0;
  st.p[kept] = eos_pressure(al, 1.0 / 0.9 - 1.0, 2.0 / st.vol0[kept]) + 1e9;
  st.vol[hot] = 0.9 * st.vol0[hot];
  st.e_int[hot] = 20e6 * al.density * st.vol0[hot];
  st.p[hot] = 3e9;
  ASSERT_GT(eos_pressure(al, -0.5, st.e_int[hot] / st.vol0[hot]), st.p[hot]);
  ASSERT_GT(eos_pressure(al, 0.25, 2.0 / st.vol0[eroded]), 3.0 * st.p[eroded]);
  const Totals before = totals(st);
  const State cells = st;

  Fragmentation frag(model.mesh, Fragments::cells, 1.3);
  frag.erode({eroded, kept, hot});
  EXPECT_EQ(frag.convert(model.mesh, model.materials, st), 4);
  ASSERT_EQ(st.particle_count(), 4);
  ASSERT_EQ(st.sph.size(), 4);
  Index e = -1, d = -1, k = -1, g = -1;
  for (Index i = 0; i < 4; ++i) {
    const Index t = st.particle_tet[i], node = st.first_particle + i;
    (t == eroded ? e : t == drawn ? d : t == kept ? k : g) = i;
    SCOPED_TRACE(t == eroded ? "eroded" : t == drawn ? "drawn out" : t == kept ? "kept" : "hot");
    EXPECT_EQ(st.sph.s[i], cells.s[t]);
    EXPECT_EQ(st.sph.p[i], cells.p[t]);
    EXPECT_EQ(st.sph.eps_p[i], cells.eps_p[t]);
    EXPECT_EQ(st.sph.temperature[i], cells.temperature[t]);
    EXPECT_EQ(st.sph.sound2[i], cells.sound2[t]);
    EXPECT_EQ(st.sph.damage[i], cells.damage[t]);
    EXPECT_EQ(st.sph.material[i], cells.tet_material[t]);
    EXPECT_EQ(st.sph.vol0[i], cells.vol0[t]);
    EXPECT_DOUBLE_EQ(st.sph.h[i], 1.3 * std::cbrt(cells.vol0[t]));
    EXPECT_DOUBLE_EQ(st.sph.rho[i] * st.sph.vol[i], st.m[node]);
  }
  ASSERT_TRUE(e >= 0 && d >= 0 && k >= 0 && g >= 0);
  // The crushed cell: at the volume where its EOS at its energy reads its 3 GPa, larger than its
  // own; the other keeps its volume.
  EXPECT_GT(st.sph.vol[e], cells.vol[eroded]);
  EXPECT_LT(st.sph.vol[e], cells.vol0[eroded]);
  EXPECT_NEAR(eos_pressure(al, st.sph.vol0[e] / st.sph.vol[e] - 1.0,
                           st.particle_energy[e] / st.sph.vol0[e]),
              3e9, 1e-9 * 3e9);
  EXPECT_EQ(st.sph.vol[k], cells.vol[kept]);
  // The hot one: held at twice its reference volume, the largest a conversion gives.
  EXPECT_EQ(st.sph.vol[g], 2.0 * cells.vol0[hot]);
  // The drawn-out cell: p(V, E) = 0 at its volume (k μ + Γ E / V0 with Mie–Grüneisen), well
  // below 50 V0.
  const double mu = st.sph.vol0[d] / st.sph.vol[d] - 1.0;
  if (heat < al.tillotson.e_cv || al.eos != EosKind::tillotson) {
    EXPECT_LT(st.sph.vol[d], 2.0 * st.sph.vol0[d]);
    EXPECT_GT(st.sph.vol[d], st.sph.vol0[d]);
    EXPECT_NEAR(eos_pressure(al, mu, st.particle_energy[d] / st.sph.vol0[d]), 0.0, 1e-6 * 3e9);
  } else {  // a hot Tillotson state is a gas, with no zero: held at twice V0, its pressure > 0
    EXPECT_DOUBLE_EQ(st.sph.vol[d], 2.0 * st.sph.vol0[d]);
    EXPECT_GT(eos_pressure(al, mu, st.particle_energy[d] / st.sph.vol0[d]), 0.0);
  }
  const Totals after = totals(st);
  EXPECT_NEAR(after.mass, before.mass, 1e-15 * before.mass);
  EXPECT_NEAR((after.momentum - before.momentum).norm(), 0.0, 1e-14 * before.mass);
  EXPECT_NEAR(after.energy, before.energy, 1e-13 * before.energy);
}

TEST(Fragmentation, AnSphParticleKeepsItsCellsState) {
  Material al = test::aluminium();
  al.eos = EosKind::mie_gruneisen;
  al.c0 = 5240;
  al.s = 1.4;
  al.gamma0 = 2.0;
  al.bulk_modulus = al.density * al.c0 * al.c0;
  particle_keeps_cells_state(al);
  SCOPED_TRACE("tillotson");
  al.eos = EosKind::tillotson;
  al.tillotson = {0.5, 1.63, 75.2e9, 65.0e9, 5.0e6, 3.0e6, 13.9e6, 5.0, 5.0};
  al.bulk_modulus = al.tillotson.big_a;
  particle_keeps_cells_state(al);
  SCOPED_TRACE("tillotson, 20 MJ/kg");
  particle_keeps_cells_state(al, 20e6);
}
