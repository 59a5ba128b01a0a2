// Spall (seed 000's failure model) in a 1-D plate impact: the spall plane where the release
// waves meet, and no damage below the velocity whose pulse reaches the spall strength.
#include <gtest/gtest.h>

#include "../test_util.hpp"
#include "tetcontact/app/setup.hpp"
#include "tetcontact/diagnostics/balance.hpp"
#include "tetcontact/io/case.hpp"
#include "tetcontact/solver/simulation.hpp"

using namespace tc;

namespace {

struct SpallRun {
  double first_z = 0.0;  // mean reference z of the cells damaged first, m
  long first_cells = 0;
  long failed = 0;  // damaged or destroyed at the end
  double momentum_error = 0.0, balance_error = 0.0;
  double last_dt = 0.0;
};

SpallRun run_spall(double speed) {
  const Case c = load_case(test::source_path("data/cases/spall-plate.yaml"),
                           {"bodies.0.velocity=[0,0,-" + std::to_string(speed) + "]"});
  Simulation sim(build_model(c), solver_settings(c));
  const Mesh& mesh = sim.model().mesh;
  SpallRun r;
  while (!sim.done()) {
    sim.step();
    if (r.first_cells > 0) continue;
    const State& st = sim.state();
    double z = 0.0;
    for (std::size_t t = 0; t < st.damage.size(); ++t)
      if (st.damage[t] != Damage::intact) {
        for (Index k : mesh.tets[t]) z += 0.25 * mesh.x[k].z();  // reference position
        ++r.first_cells;
      }
    if (r.first_cells > 0) r.first_z = z / static_cast<double>(r.first_cells);
  }
  sim.finish();
  for (const Damage d : sim.state().damage) r.failed += d != Damage::intact;
  r.momentum_error = momentum_error(sim.first_sample(), sim.last_sample());
  r.balance_error = sim.balance_error_max();
  r.last_dt = sim.state().dt;
  return r;
}

}  // namespace

// Flyer 2 mm on target 4 mm, same alloy, 400 m/s: the releases from the two free faces meet
// at the flyer's thickness from the target's rear face, z = −2 mm (reference position); the
// first cells to spall lie within two cells (0.1 mm) of it (measured: −2.034 mm).
TEST(Validation, SpallPlaneWhereTheReleasesMeet) {
  const SpallRun r = run_spall(400.0);
  ASSERT_GT(r.first_cells, 0);
  EXPECT_NEAR(r.first_z, -2.0e-3, 2 * 0.05e-3);
  EXPECT_LT(r.momentum_error, 1e-12);
  EXPECT_LT(r.balance_error, 0.02);
  // No cell is crushed next to the failed ones (regression: with failed cells in the nodal
  // pressure averages the step fell from 4e-9 to 6e-12 s): measured 1.9e-9 s at the end.
  EXPECT_GT(r.last_dt, 1e-9);
}

// At 150 m/s the pulse (about ρ c u_p + 2Y/3 ≈ 1.3 GPa) stays below σ* = 1.6 GPa: no cell
// fails (the threshold measured on this mesh lies between 230 and 250 m/s).
TEST(Validation, NoSpallBelowTheThreshold) {
  const SpallRun r = run_spall(150.0);
  EXPECT_EQ(r.first_cells, 0);
  EXPECT_EQ(r.failed, 0);
  EXPECT_LT(r.momentum_error, 1e-12);
}
