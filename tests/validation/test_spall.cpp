// Spall (Dobritsa et al.'s failure model) in a 1-D plate impact: the spall plane where the release
// waves meet, and no damage below the velocity whose pulse reaches the spall strength.
#include <gtest/gtest.h>

#include "../test_util.hpp"
#include "tetcontact/app/setup.hpp"
#include "tetcontact/diagnostics/balance.hpp"
#include "tetcontact/diagnostics/gauges.hpp"
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
  EXPECT_LT(r.balance_error, 5e-4);  // 4.3e-5 measured
  // No cell is crushed next to the failed ones (regression: with failed cells in the nodal
  // pressure averages the step fell from 4e-9 to 6e-12 s): measured 1.9e-9 s at the end.
  EXPECT_GT(r.last_dt, 1e-9);
}

// The threshold from theory: two equal plates meeting at v have u_p = v/2 behind the shocks;
// the releases meeting at the spall plane turn the pulse ρ0 c0 u_p into a tension of the same
// size, which reaches σ* = 1.6 GPa at v* = 2σ*/(ρ0 c0) = 2 · 1.6e9 / (2703 · 5240) = 226 m/s.
// The check brackets it closely on both sides: no cell fails at 215 m/s (0.95 v*), cells fail at
// 260 m/s (1.15 v*). Measured on this mesh: none up to 240 m/s, spall from 245 m/s (8 cells),
// 7–8 % above the acoustic estimate.
TEST(Validation, SpallThresholdBracketedFromTheory) {
  const double v_star = 2.0 * 1.6e9 / (2703.0 * 5240.0);
  ASSERT_NEAR(v_star, 226.0, 0.5);
  const SpallRun below = run_spall(0.95 * v_star);
  EXPECT_EQ(below.first_cells, 0);
  EXPECT_EQ(below.failed, 0);
  EXPECT_LT(below.momentum_error, 1e-12);
  const SpallRun above = run_spall(1.15 * v_star);
  EXPECT_GT(above.first_cells, 0);
  EXPECT_NEAR(above.first_z, -2.0e-3, 2 * 0.05e-3);  // at the plane where the releases meet
}

namespace {

// The rear face's gauge (the case's `gauges:`) read at every step: time and velocity along z.
std::vector<std::pair<double, double>> rear_face_velocity(const std::vector<std::string>& sets) {
  const Case c = load_case(test::source_path("data/cases/spall-plate.yaml"), sets);
  Simulation sim(build_model(c), solver_settings(c));
  Gauges gauges(sim.model().mesh, c.output.gauges);
  EXPECT_EQ(gauges.specs().at(0).name, "rear face");
  std::vector<std::pair<double, double>> out;
  while (!sim.done()) {
    sim.step();
    out.emplace_back(sim.state().t, gauges.read(sim.state()).at(0).v.z());
  }
  sim.finish();
  return out;
}

}  // namespace

// The free-surface velocity a VISAR would record on the target's rear face (the case's gauge).
// The face leaves at u_fs = 2 u_p = v0 (equal impedances: u_p = v0/2) within 3 %; when the
// target spalls, the release is cut off at the spall plane and the face is pulled back by Δu_fs
// and re-accelerated (the spall signal). The classic estimate ½ ρ0 c0 Δu_fs reads the spall
// strength from the pull-back: measured 138 m/s, 0.98 GPa against the model's σ* = 1.6 GPa
// (docs/validation/spall.md says why they differ); held between 0.5 and 1.0 σ*. Without
// fracture the face falls on toward rest with no signal: the check fails.
TEST(Validation, SpallFreeSurfacePullBackAndTheStrengthItImplies) {
  const Case c = load_case(test::source_path("data/cases/spall-plate.yaml"));
  const Material& al = c.material("al");
  const double v0 = 400.0, sigma_star = al.spall_strength;
  ASSERT_EQ(sigma_star, 1.6e9);
  struct Signal {
    double peak = 0.0, pull_back = 1e9, after = 0.0;
  };
  const auto signal = [](const std::vector<std::pair<double, double>>& u) {
    Signal s;
    std::size_t ip = 0;
    for (std::size_t i = 0; i < u.size(); ++i)
      if (u[i].first < 1.2e-6 && -u[i].second > s.peak) s.peak = -u[i].second, ip = i;
    std::size_t im = ip;
    for (std::size_t i = ip; i < u.size() && u[i].first < 1.6e-6; ++i)
      if (-u[i].second < s.pull_back) s.pull_back = -u[i].second, im = i;
    for (std::size_t i = im; i < u.size(); ++i) s.after = std::max(s.after, -u[i].second);
    return s;
  };
  const Signal on = signal(rear_face_velocity({}));
  EXPECT_NEAR(on.peak, v0, 0.03 * v0);
  const double du = on.peak - on.pull_back;
  const double estimate = 0.5 * al.density * al.bulk_sound_speed() * du;
  EXPECT_GT(estimate, 0.5 * sigma_star) << du;
  EXPECT_LT(estimate, 1.0 * sigma_star) << du;
  EXPECT_GT(on.after - on.pull_back, 0.5 * du);  // the spall signal
  const Signal off = signal(rear_face_velocity({"fracture.enabled=false"}));
  EXPECT_NEAR(off.peak, v0, 0.03 * v0);
  EXPECT_LT(off.pull_back, 0.5 * on.pull_back);     // no spall: released toward rest
  EXPECT_LT(off.after - off.pull_back, 0.25 * du);  // and no signal
}
