// A longitudinal wave travels at the material's wave speed.
#include <gtest/gtest.h>

#include "solver_fixture.hpp"
#include "tetcontact/diagnostics/balance.hpp"
#include "tetcontact/solver/simulation.hpp"

using namespace tc;

namespace {

// Observer that records the mean axial velocity of the nodes in one cross-section.
class Station : public Observer {
 public:
  Station(std::vector<Index> nodes) : nodes_(std::move(nodes)) {}
  void observe(const State& st, const Sample& s) override {
    double v = 0.0;
    for (Index i : nodes_) v += centred_velocity(st, i).x();
    t.push_back(s.t);
    u.push_back(v / static_cast<double>(nodes_.size()));
  }
  // Time at which the velocity first reaches `level` (linear interpolation between samples).
  double arrival(double level) const {
    for (std::size_t k = 1; k < u.size(); ++k)
      if (u[k] >= level)
        return t[k - 1] + (level - u[k - 1]) / (u[k] - u[k - 1]) * (t[k] - t[k - 1]);
    return -1.0;
  }
  std::vector<double> t, u;

 private:
  std::vector<Index> nodes_;
};

}  // namespace

// Uniaxial strain: a bar with rollers on its sides (no lateral motion), pushed at one end
// with v0. Theory: a step front moving at c = sqrt((K + 4G/3)/ρ) carrying particle velocity
// v0 and stress ρ c v0. The front's half-amplitude crossing arrives at x at t = x / c.
TEST(Wave, LongitudinalWaveSpeedWithinTwoPercent) {
  const double L = 0.2, v0 = 1.0;
  const Material mat = test::aluminium(0.3);
  Model model =
      test::single_body_model(make_box(Vec3(L, 0.004, 0.004), {200, 2, 2}, HexSplit::six), mat);
  VelocityConstraint rollers, piston;
  rollers.name = "rollers";
  rollers.components = {false, true, true};
  piston.name = "piston";
  piston.components = {true, false, false};
  piston.velocity = Vec3(v0, 0, 0);
  std::vector<Index> near, far;
  const double x_near = -L / 2 + 0.05, x_far = -L / 2 + 0.15;
  for (Index i = 0; i < model.mesh.node_count(); ++i) {
    const double x = model.mesh.x[i].x();
    rollers.nodes.push_back(i);
    if (x < -L / 2 + 1e-12) piston.nodes.push_back(i);
    if (std::abs(x - x_near) < 1e-9) near.push_back(i);
    if (std::abs(x - x_far) < 1e-9) far.push_back(i);
  }
  ASSERT_FALSE(near.empty());
  ASSERT_FALSE(far.empty());
  for (Index i : piston.nodes) model.initial_velocity[i].x() = v0;
  model.constraints = {rollers, piston};
  const double c = mat.wave_speed();
  SolverSettings settings;
  settings.end_time = 0.18 / c;  // before the front reaches the far end
  Simulation sim(std::move(model), settings);
  Station a(near), b(far);
  sim.add_observer(&a, "station-near");
  sim.add_observer(&b, "station-far");
  while (!sim.done()) sim.step();
  const double ta = a.arrival(0.5 * v0), tb = b.arrival(0.5 * v0);
  ASSERT_GT(ta, 0.0);
  ASSERT_GT(tb, ta);
  const double c_measured = (x_far - x_near) / (tb - ta);
  EXPECT_NEAR(c_measured / c, 1.0, 0.02) << "measured " << c_measured << " m/s, theory " << c;
  RecordProperty("measured_wave_speed", std::to_string(c_measured));
  RecordProperty("theory_wave_speed", std::to_string(c));
  // Behind the front the stress is the impedance's ρ c v0 (compression, −σxx = p + q − s_xx):
  // the mean over the tets between the piston and the near station at the end.
  const State& st = sim.state();
  double sigma = 0.0;
  long n = 0;
  for (std::size_t t = 0; t < st.p.size(); ++t) {
    double x = 0.0;
    for (Index k : sim.model().mesh.tets[t]) x += 0.25 * st.x[k].x();
    if (x < -L / 2 + 0.01 || x > x_near) continue;
    sigma += st.p[t] + st.q[t] - st.s[t][0];
    ++n;
  }
  ASSERT_GT(n, 0);
  EXPECT_NEAR(sigma / n / (mat.density * c * v0), 1.0, 1e-3);  // −1.2e-4 measured
}
