// Contact heat: each exchange's loss of kinetic energy, exact; its split between the sides, the
// loss of each in the pair's centre-of-mass frame; a node's heat into the cells around it by the
// mass each gives it, or into the particle it is.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>

#include "../test_util.hpp"
#include "contact_points.hpp"
#include "tetcontact/response/heat.hpp"
#include "tetcontact/response/impulse.hpp"

using namespace tc;

namespace {

// Each node's heat from the contacts of one list booked in st.contact_impulse.
std::vector<double> heat_of(std::vector<ContactPoint>& points, const State& st,
                            const std::vector<std::uint8_t>& planes = {}) {
  const std::vector<ContactList> lists{
      {&points, const_cast<std::vector<Vec3>*>(&st.contact_impulse)}};
  std::vector<Index> slot;
  const Islands islands = contact_islands(lists, st.x.size(), slot);
  std::vector<double> heat(st.x.size(), 0.0);
  node_heat(lists, {1}, planes, islands, st, heat);
  return heat;
}

double kinetic(const State& st) {
  double k = 0.0;
  for (std::size_t i = 0; i < st.m.size(); ++i) k += 0.5 * st.m[i] * st.v_star[i].squaredNorm();
  return k;
}

}  // namespace

// Two points meeting head on and stopping together (a perfectly inelastic collision): the heat
// is ½ μ v², μ = m1 m2 / (m1 + m2), and node 1 takes m2 / (m1 + m2) of it, its own loss in the
// frame of the centre of mass, ½ m1 (v1 − v_cm)².
TEST(ContactHeat, AnInelasticCollisionHeatsEachSideByItsLossInTheCentreOfMassFrame) {
  State st;
  st.x = {Vec3::Zero(), Vec3::Zero()};
  const double m1 = 1.0e-3, m2 = 4.0e-3, v1 = -2500.0, v2 = 10.0;
  st.v_star = {Vec3(0, 0, v1), Vec3(0, 0, v2)};
  st.v = st.v_star;  // no force this step: the booked work is the exchange's loss
  st.m = {m1, m2};
  st.contact_impulse.assign(2, Vec3::Zero());
  ContactPoint c = test::node_against_node(0, 1);  // node 0 above node 1, normal +z from B to A
  c.gap = -1.0;                                    // penetrated: the target is the common velocity
  const double k0 = kinetic(st);
  apply_contact(c, st, 1e-9, st.contact_impulse);
  EXPECT_NEAR(st.v_star[0].z(), st.v_star[1].z(), 1e-9);
  const double mu = m1 * m2 / (m1 + m2), v = v1 - v2;
  EXPECT_NEAR(c.heat, 0.5 * mu * v * v, 1e-12 * c.heat);
  EXPECT_NEAR(c.heat, k0 - kinetic(st), 1e-12 * c.heat);
  std::vector<ContactPoint> points{c};
  const std::vector<double> heat = heat_of(points, st);
  const double v_cm = (m1 * v1 + m2 * v2) / (m1 + m2);
  EXPECT_NEAR(heat[0], 0.5 * m1 * (v1 - v_cm) * (v1 - v_cm), 1e-12 * c.heat);
  EXPECT_NEAR(heat[1], 0.5 * m2 * (v2 - v_cm) * (v2 - v_cm), 1e-12 * c.heat);
  EXPECT_NEAR(heat[0] / c.heat, m2 / (m1 + m2), 1e-12);
  // Node 0 on a symmetry plane stands for a node of the whole of mass 2 m1: it shares as that.
  const std::vector<double> mirrored = heat_of(points, st, {1, 0});
  EXPECT_NEAR(mirrored[0] / c.heat, m2 / (2 * m1 + m2), 1e-12);
  EXPECT_NEAR(mirrored[0] + mirrored[1], c.heat, 1e-12 * c.heat);
}

// A node against a face at random weights, with Coulomb friction: the heat the kernel books is
// the kinetic energy the pair lost, normal and sliding; the nodes get the booked work of the
// step, shared as the exchange's loss is (w²/m).
TEST(ContactHeat, TheKernelsHeatIsTheLostKineticEnergyWithFriction) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  for (int k = 0; k < 100; ++k) {
    State st;
    for (int i = 0; i < 4; ++i) {
      st.x.push_back(Vec3::Zero());
      st.v_star.push_back(Vec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5));
      st.m.push_back(0.5 + u(rng));
    }
    st.v_star[0].z() -= 2.0;  // closing
    // Uⁿ⁻½ = U* − τa: the step's forces also moved the nodes, by a random kick.
    st.v = st.v_star;
    if (k % 2) st.v[k % 4] += Vec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5);
    st.contact_impulse.assign(4, Vec3::Zero());
    const double w1 = u(rng), w2 = (1 - w1) * u(rng);
    ContactPoint c = test::node_against_face(0, {1, 2, 3}, w1, w2);
    c.gap = -1e-3;
    c.mode = FrictionMode::coulomb;
    c.friction = 0.3;
    const double k0 = kinetic(st);
    for (int pass = 0; pass < 3; ++pass) apply_contact(c, st, 1e-3, st.contact_impulse);
    EXPECT_GT(c.heat, 0.0);
    EXPECT_NEAR(c.heat, k0 - kinetic(st), 1e-12 * k0);
    // The island's heat is the work the balance books, Σ j·(Uⁿ⁻½ + Uⁿ⁺½)/2 (the exchange's own
    // loss where the forces did not kick), shared as the exchange's loss is.
    double work = 0.0;
    for (int i = 0; i < 4; ++i) work += 0.5 * st.contact_impulse[i].dot(st.v[i] + st.v_star[i]);
    std::vector<ContactPoint> points{c};
    const std::vector<double> heat = heat_of(points, st);
    const double sum = heat[0] + heat[1] + heat[2] + heat[3];
    if (work < 0.0) {
      EXPECT_NEAR(sum, -work, 1e-13 * k0);
      if (k % 2 == 0) {
        EXPECT_NEAR(sum, c.heat, 1e-13 * k0);
      }
      for (int i = 0; i < 4; ++i) {
        const double w = i == 0 ? 1.0 : c.b_w[i - 1];
        EXPECT_NEAR(heat[i],
                    sum * (w * w / st.m[i]) /
                        (1 / st.m[0] + c.b_w[0] * c.b_w[0] / st.m[1] +
                         c.b_w[1] * c.b_w[1] / st.m[2] + c.b_w[2] * c.b_w[2] / st.m[3]),
                    1e-13 * k0);
      }
    } else {
      EXPECT_EQ(sum, 0.0);  // the forces' kick outweighed the loss: nothing deposited
    }
  }
}

// A node stopped by a symmetry plane's wall (its mirror image) keeps its loss as heat; by a
// rigid wall, not: the wall's loss is its work. Both at once on one node (one island): only the
// plane's loss is heat, the rigid wall's work not counted in the island's.
TEST(ContactHeat, ASymmetryPlaneHeatsWhatStrikesItAndARigidWallDoesNot) {
  const auto wall_point = [](const Vec3& normal) {
    ContactPoint c;
    c.a_nodes[0] = 0;
    c.a_w[0] = 1;
    c.a_count = 1;
    c.b_count = 0;  // a wall
    c.normal = normal;
    c.gap = -1.0;  // the target: stopped along the normal
    return c;
  };
  State st;
  st.x = {Vec3::Zero()};
  st.v_star = {Vec3(-1, 0, -3)};
  st.v = st.v_star;
  st.m = {2.0};
  st.wall_impulse.assign(1, Vec3::Zero());
  std::vector<ContactPoint> rigid{wall_point(Vec3::UnitX())}, plane{wall_point(Vec3::UnitZ())};
  apply_contact(rigid[0], st, 1e-6, st.wall_impulse);
  apply_contact(plane[0], st, 1e-6, st.wall_impulse);
  EXPECT_NEAR(rigid[0].heat, 1.0, 1e-12);  // ½ m 1²
  EXPECT_NEAR(plane[0].heat, 9.0, 1e-12);  // ½ m 3²
  const std::vector<ContactList> lists{{&rigid, &st.wall_impulse}, {&plane, &st.wall_impulse}};
  std::vector<Index> slot;
  const Islands islands = contact_islands(lists, 1, slot);
  ASSERT_EQ(islands.count(), 1u);
  for (const std::vector<char>& heats :
       {std::vector<char>{0, 1}, std::vector<char>{0, 0}, std::vector<char>{1, 1}}) {
    std::vector<double> heat(1, 0.0);
    node_heat(lists, heats, {}, islands, st, heat);
    EXPECT_NEAR(heat[0], 1.0 * heats[0] + 9.0 * heats[1], 1e-12);
  }
}

// Two tets sharing the face (1, 2, 3) and a particle: a node's heat goes to its cells by the
// mass each gives it, the particle's to the particle, and the total is what was given.
TEST(ContactHeat, ANodesHeatGoesToItsCellsByTheirMassAndAParticlesToIt) {
  Material light, heavy;
  light.density = 1000.0;
  heavy.density = 3000.0;
  heavy.specific_heat = 500.0;
  const std::vector<Tet> tets = {{0, 1, 2, 3}, {4, 1, 2, 3}};
  State st;
  st.vol0 = {1.0e-9, 2.0e-9};
  st.e_int = {1.0, 2.0};
  st.tet_material = {0, 1};
  st.temperature = {300.0, 300.0};
  st.damage = {Damage::intact, Damage::intact};
  st.m.assign(5, 0.0);
  for (std::size_t t = 0; t < 2; ++t)
    for (Index k : tets[t]) st.m[k] += 0.25 * (t == 0 ? 1000.0 : 3000.0) * st.vol0[t];
  st.first_particle = 5;
  st.m.push_back(1.0e-6);  // the particle, node 5
  st.particle_radius = {1.0e-4};
  st.particle_energy = {0.5};
  st.particle_tet = {0};
  std::vector<double> heat = {0.0, 0.7, 0.0, 0.0, 0.0, 0.25};
  const double total = deposit_heat(tets, {light, heavy}, heat, st);
  EXPECT_EQ(total, 0.95);
  // Node 1 holds 0.25 e-6 kg of tet 0 and 1.5 e-6 kg of tet 1: 1/7 and 6/7 of its 0.7 J.
  EXPECT_NEAR(st.e_int[0], 1.0 + 0.1, 1e-15);
  EXPECT_NEAR(st.e_int[1], 2.0 + 0.6, 1e-15);
  EXPECT_EQ(st.temperature[0], 300.0);  // no specific heat: not tracked
  EXPECT_NEAR(st.temperature[1], 300.0 + 0.6 / (3000.0 * 2.0e-9 * 500.0), 1e-9);
  EXPECT_EQ(st.particle_energy[0], 0.75);
}

// Two cubes crushing each other (cubes-edge.yaml): with the heat the contact work comes back as
// internal energy and the total stays where it started; without it the total falls by the
// contact work, booked and nowhere else.
TEST(ContactHeat, TheContactWorkBecomesInternalEnergyAndTheTotalIsKept) {
  test::TempDir dir("contact-heat");
  const std::string cubes = "'" + test::source_path("data/cases/cubes-edge.yaml") + "'";
  test::Json on, off;
  for (const bool heat : {true, false}) {
    const std::string out = dir.str() + (heat ? "/on" : "/off");
    const auto r = test::run_cli("run " + cubes + " --quiet --out '" + out +
                                     "' --set contact.heat=" + (heat ? "true" : "false"),
                                 dir.str());
    ASSERT_EQ(r.code, 0) << r.err;
    (heat ? on : off) = test::read_json(out + "/summary.json");
  }
  const double work = test::number(on, "/energy/contact_work");
  const double heat = test::number(on, "/energy/contact_heat");
  const double first = test::number(on, "/energy/total_initial");
  EXPECT_LT(work, -0.05 * first);  // the crush dissipates: measured −144.5 of 1,729.9 J
  // The heat is the booked work of the islands that dissipated: 144.529 J against a total of
  // −144.508 J (islands whose passes gave energy back, W > 0, deposit nothing).
  EXPECT_NEAR(heat, -work, 1e-3 * -work);
  EXPECT_LT(std::abs(test::number(on, "/energy/total_final") - first), 1e-3 * first);
  EXPECT_LT(test::number(on, "/energy/balance_error_max"), 1e-3);
  EXPECT_EQ(test::number(off, "/energy/contact_heat"), 0.0);
  const double work_off = test::number(off, "/energy/contact_work");
  EXPECT_NEAR(test::number(off, "/energy/total_final"), first + work_off, 1e-3 * first);
  EXPECT_GT(test::number(on, "/energy/internal") - test::number(off, "/energy/internal"),
            0.5 * heat);
}
