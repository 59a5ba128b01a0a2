// Rigid walls: the exchange itself, and an elastic bar striking a wall against 1-D theory.
#include <gtest/gtest.h>

#include "../solver/solver_fixture.hpp"
#include "tetcontact/response/wall.hpp"
#include "tetcontact/solver/run_loop.hpp"
#include "tetcontact/solver/simulation.hpp"

using namespace tc;

namespace {

State one_node(const Vec3& x, const Vec3& u_star, double m, double dt) {
  State st;
  st.x = {x};
  st.v = {u_star};
  st.v_star = {u_star};
  st.m = {m};
  st.wall_impulse = {Vec3::Zero()};
  st.dt = dt;
  return st;
}

}  // namespace

TEST(Wall, NodeLandsOnThePlaneAndWallsNeverPull) {
  RigidWall wall;
  wall.normal = Vec3(0, 0, 1);
  // 1 mm above the plane at −10 m/s, τ = 1e-3 s: it would travel 10 mm; it must stop on the plane.
  State st = one_node(Vec3(0, 0, 1e-3), Vec3(3, 0, -10), 2.0, 1e-3);
  auto r = apply_walls({wall}, {0}, st);
  EXPECT_NEAR(st.v_star[0].z(), -1.0, 1e-12);  // −d/τ
  EXPECT_NEAR(st.x[0].z() + st.dt * st.v_star[0].z(), 0.0, 1e-15);
  EXPECT_EQ(st.v_star[0].x(), 3.0);                 // no friction: tangential kept
  EXPECT_NEAR(r[0].impulse.z(), 2.0 * 9.0, 1e-12);  // m Δv
  EXPECT_EQ(r[0].contacts, 1);
  // Moving away, or not reaching the plane: untouched.
  st = one_node(Vec3(0, 0, 1e-3), Vec3(0, 0, +1), 2.0, 1e-3);
  r = apply_walls({wall}, {0}, st);
  EXPECT_EQ(st.v_star[0].z(), 1.0);
  EXPECT_EQ(r[0].contacts, 0);
  st = one_node(Vec3(0, 0, 1e-3), Vec3(0, 0, -0.5), 2.0, 1e-3);
  apply_walls({wall}, {0}, st);
  EXPECT_EQ(st.v_star[0].z(), -0.5);
}

TEST(Wall, AParticleStopsItsRadiusFromThePlane) {
  RigidWall wall;
  wall.normal = Vec3(0, 0, 1);
  // A body node (index 0) far above, and a particle of radius 0.4 mm (node 1) whose centre is
  // 1 mm above the plane at −10 m/s: its sphere would cross; it stops 0.4 mm above the plane.
  State st = one_node(Vec3(0, 0, 1.0), Vec3(0, 0, -10), 1.0, 1e-3);
  st.x.push_back(Vec3(0, 0, 1e-3));
  st.v.push_back(Vec3(0, 0, -10));
  st.v_star.push_back(Vec3(0, 0, -10));
  st.m.push_back(3.0);
  st.wall_impulse.push_back(Vec3::Zero());
  st.first_particle = 1;
  st.particle_radius = {0.4e-3};
  const auto r = apply_walls({wall}, {0}, st);
  EXPECT_NEAR(st.x[1].z() + st.dt * st.v_star[1].z(), 0.4e-3, 1e-15);
  EXPECT_NEAR(r[0].impulse.z(), 3.0 * (10.0 - 0.6), 1e-12);
  EXPECT_EQ(r[0].contacts, 1);
  EXPECT_EQ(st.v_star[0].z(), -10.0);  // the body node does not reach the plane
}

TEST(Wall, CoulombFrictionSticksOrSlips) {
  RigidWall wall;
  wall.normal = Vec3(0, 0, 1);
  wall.friction = 0.5;
  // On the plane, normal impulse m·10; stick needs m·2 ≤ 0.5·m·10: sticks.
  State st = one_node(Vec3::Zero(), Vec3(2, 0, -10), 1.0, 1e-3);
  apply_walls({wall}, {0}, st);
  EXPECT_NEAR(st.v_star[0].norm(), 0.0, 1e-12);
  // Stick would need m·8 > 0.5·m·10: slips, tangential speed reduced by k·λ/m = 5.
  st = one_node(Vec3::Zero(), Vec3(8, 0, -10), 1.0, 1e-3);
  apply_walls({wall}, {0}, st);
  EXPECT_NEAR(st.v_star[0].x(), 3.0, 1e-12);
  EXPECT_NEAR(st.v_star[0].z(), 0.0, 1e-12);
}

namespace {

class WallForce : public Observer {
 public:
  void observe(const State&, const Sample& s) override {
    t.push_back(s.t);
    f.push_back(s.wall_force.empty() ? 0.0 : s.wall_force[0]);
  }
  std::vector<double> t, f;
};

}  // namespace

// An elastic bar (ν = 0: bar and dilatational speeds coincide, c = sqrt(E/ρ)) strikes a rigid
// wall end-on at v0. 1-D theory: contact lasts 2L/c, the wall force is ρ c v0 A while it
// lasts, and the bar leaves with −v0. Momentum: the change equals the wall's impulse.
TEST(Wall, ElasticBarOnWallMatchesOneDimensionalTheory) {
  const double L = 0.1, a = 0.01, v0 = 5.0;
  const Material mat = test::aluminium(0.0);
  TetMesh mesh = make_box(Vec3(a, a, L), {2, 2, 40}, HexSplit::six);
  translate(mesh, Vec3(0, 0, L / 2));  // bottom face on the plane z = 0
  Model model = test::single_body_model(mesh, mat);
  model.element.viscosity_linear = 0.06;  // the defaults: the bar still rebounds elastically
  model.element.viscosity_quadratic = 1.5;
  for (Vec3& v : model.initial_velocity) v = Vec3(0, 0, -v0);
  RigidWall wall;
  wall.name = "floor";
  model.walls = {wall};
  const double c = std::sqrt(mat.youngs_modulus() / mat.density);
  SolverSettings settings;
  settings.end_time = 1.5 * 2 * L / c;
  Simulation sim(std::move(model), settings);
  WallForce probe;
  sim.add_observer(&probe, "probe");
  ASSERT_EQ(run_to_end(sim), "ok");

  double first = -1, last = -1, impulse = 0;
  for (std::size_t k = 0; k < probe.t.size(); ++k)
    if (probe.f[k] > 0) {
      if (first < 0) first = probe.t[k];
      last = probe.t[k];
      impulse += probe.f[k] * sim.last_sample().dt;
    }
  const double duration = last - first, expected = 2 * L / c;
  EXPECT_NEAR(duration / expected, 1.0, 0.05) << duration << " s vs " << expected << " s";
  const double force = mat.density * c * v0 * a * a;
  // The peak overshoots ρcv at the front by 11.8 % on this mesh (measured).
  EXPECT_NEAR(sim.wall_force_max()[0] / force, 1.0, 0.15) << "peak " << sim.wall_force_max()[0];
  const double mean_force = impulse / duration;
  EXPECT_NEAR(mean_force / force, 1.0, 0.05) << "mean " << mean_force << " N vs " << force;
  const Sample& end = sim.last_sample();
  // Rebounds at +v0, less what the discrete impact dissipates: the bulk viscosity and the
  // plastic stop of the first layer of nodes (1/80 of the energy on 40 cells).
  EXPECT_NEAR(end.momentum.z() / (end.mass * v0), 1.0, 0.05);
  // Momentum balance with the wall's impulse, and energy balance with its work.
  EXPECT_LT((end.momentum - sim.first_sample().momentum - end.external_impulse()).norm(),
            1e-12 * end.momentum_scale);
  EXPECT_LT(sim.balance_error_max(), 4e-4);  // 3.7e-5 measured
}
