// Momentum and energy over whole runs.
#include <gtest/gtest.h>

#include "../test_util.hpp"
#include "solver_fixture.hpp"
#include "tetcontact/app/setup.hpp"
#include "tetcontact/io/case.hpp"
#include "tetcontact/solver/run_loop.hpp"
#include "tetcontact/solver/simulation.hpp"

using namespace tc;

// Free flight: a spinning, translating, internally stressed body. Internal forces cancel
// tet by tet, so the momentum stays at its initial value to round-off.
TEST(Conservation, MomentumInFreeFlightToRoundOff) {
  TetMesh mesh = make_sphere(0.01, 6, HexSplit::six);
  Model model = test::single_body_model(mesh, test::aluminium());
  const Vec3 omega(3000, -1000, 2000), v0(120, -40, 75);
  for (std::size_t i = 0; i < model.mesh.x.size(); ++i) {
    const Vec3& p = model.mesh.x[i];
    // rigid motion plus a radial breathing and a shear, which load the tets
    model.initial_velocity[i] = v0 + omega.cross(p) + 2000.0 * p + Vec3(500.0 * p.y(), 0, 0);
  }
  SolverSettings settings;
  settings.end_time = 1.0;
  settings.max_steps = 500;
  Simulation sim(std::move(model), settings);
  for (int k = 0; k < 500; ++k) sim.step();
  const Sample& a = sim.first_sample();
  const Sample& b = sim.last_sample();
  EXPECT_EQ(b.step, 499);
  EXPECT_GT(b.internal, 1e-3 * b.total);  // the body is really loaded
  EXPECT_LT((b.momentum - a.momentum).norm(), 1e-13 * a.momentum_scale);
  EXPECT_NEAR(b.mass, a.mass, 0.0);
}

// The vibration case: ≥ 2,000 steps of free elastic vibration, energy balance within 0.5%.
TEST(Conservation, ElasticVibrationEnergyBalance) {
  const Case c = load_case(test::source_path("data/cases/elastic-vibration.yaml"));
  Simulation sim(build_model(c), solver_settings(c));
  ASSERT_EQ(run_to_end(sim), "ok");
  EXPECT_GE(sim.state().step, 2000);
  const Sample& first = sim.first_sample();
  // Initial kinetic energy ½ m v² with the middle plane of nodes at rest: 0.0135 J less
  // the middle plane's share (1/41 of the lattice planes, half-weight tets around it).
  EXPECT_GT(first.kinetic, 0.0130);
  EXPECT_LT(first.kinetic, 0.0135);
  EXPECT_LT(sim.balance_error_max(), 4e-4);  // 4.3e-5 measured
  // Energy really moves between kinetic and internal.
  EXPECT_GT(sim.last_sample().internal, 0.01 * first.kinetic);
  EXPECT_LT((sim.last_sample().momentum - first.momentum).norm(), 1e-12 * first.momentum_scale);
}

// Prescribed velocity: the boundary work closes the energy balance of a driven bar.
TEST(Conservation, BoundaryWorkClosesDrivenBar) {
  Model model = test::single_body_model(make_box(Vec3(0.1, 0.01, 0.01), {40, 4, 4}, HexSplit::six),
                                        test::aluminium());
  VelocityConstraint push;
  push.name = "push";
  push.velocity = Vec3(2.0, 0, 0);
  push.components = {true, false, false};
  for (Index i = 0; i < model.mesh.node_count(); ++i)
    if (model.mesh.x[i].x() < -0.05 + 1e-12) push.nodes.push_back(i);
  for (Index i : push.nodes) model.initial_velocity[i].x() = 2.0;
  model.constraints.push_back(push);
  SolverSettings settings;
  settings.end_time = 1.5e-5;  // the wave travels 0.09 m: not yet reflected
  Simulation sim(std::move(model), settings);
  ASSERT_EQ(run_to_end(sim), "ok");
  const Sample& s = sim.last_sample();
  EXPECT_GT(s.boundary.work, 0.0);
  EXPECT_LT(sim.balance_error_max(), 5e-6);  // 5.0e-7 measured
  // Momentum gained equals the impulse the boundary gave.
  EXPECT_LT((s.momentum - sim.first_sample().momentum - s.boundary.impulse).norm(),
            1e-9 * s.momentum_scale);
}
