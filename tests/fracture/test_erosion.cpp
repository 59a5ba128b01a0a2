// Erosion by the step (fracture.erosion_step_ratio): a cell becomes a particle when its stable
// step falls below a fraction of the first step, the whole model's or its own body's
// (fracture.erosion_reference). The limits against each body's smallest l/c computed here from
// its tets, and which cells a compression erodes under each reference.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "../solver/solver_fixture.hpp"
#include "tetcontact/solver/simulation.hpp"

using namespace tc;

namespace {

constexpr double k_ratio = 0.5;

// A fine cube (1 mm cells) and, 10 mm beside it, a coarse one (4 mm cells), both aluminium,
// the default bulk viscosity; the coarse one under a uniform compression at rate `rate`
// (v = −rate (x − centre)), the fine one at rest.
Model two_cubes(bool per_body, double rate) {
  Material m = test::aluminium();
  m.spall_strength = 1e12;  // no spall: only erosion makes particles
  TetMesh fine = make_box(Vec3(4e-3, 4e-3, 4e-3), {4, 4, 4}, HexSplit::six);
  TetMesh coarse = make_box(Vec3(16e-3, 16e-3, 16e-3), {4, 4, 4}, HexSplit::six);
  const Vec3 centre(30e-3, 0.0, 0.0);
  for (Vec3& x : coarse.x) x += centre;
  Model model = test::single_body_model(std::move(fine), m);
  add_body(model.mesh, "coarse", std::move(coarse));
  model.body_material = {0, 0};
  model.surfaces = build_surfaces(model.mesh);
  model.initial_velocity.assign(model.mesh.x.size(), Vec3::Zero());
  for (Index i = model.mesh.bodies[1].node_begin; i < model.mesh.bodies[1].node_end; ++i)
    model.initial_velocity[i] = -rate * (model.mesh.x[i] - centre);
  model.element.viscosity_linear = 0.06;
  model.element.viscosity_quadratic = 1.5;
  model.element.fracture = true;
  model.particles = true;
  model.erosion_step_ratio = k_ratio;
  model.erosion_per_body = per_body;
  return model;
}

// Each body's smallest l / c at rest, l = 3V / (largest face area), from its tets' corners.
std::vector<double> smallest_steps(const Model& model) {
  const Material& m = model.materials[0];  // linear elastic: c² = (K + 4G/3) / ρ
  const double c = std::sqrt((m.bulk_modulus + 4.0 / 3.0 * m.shear_modulus) / m.density);
  std::vector<double> steps;
  for (const BodyRange& b : model.mesh.bodies) {
    double smallest = std::numeric_limits<double>::infinity();
    for (Index t = b.tet_begin; t < b.tet_end; ++t) {
      const Tet& k = model.mesh.tets[t];
      const Vec3 &p0 = model.mesh.x[k[0]], &p1 = model.mesh.x[k[1]], &p2 = model.mesh.x[k[2]],
                 &p3 = model.mesh.x[k[3]];
      const double vol = std::abs((p1 - p0).cross(p2 - p0).dot(p3 - p0)) / 6.0;
      const double area =
          0.5 * std::max({(p1 - p0).cross(p2 - p0).norm(), (p1 - p0).cross(p3 - p0).norm(),
                          (p2 - p0).cross(p3 - p0).norm(), (p2 - p1).cross(p3 - p1).norm()});
      smallest = std::min(smallest, 3.0 * vol / area / c);
    }
    steps.push_back(smallest);
  }
  return steps;
}

// The cells of each body eroded after `steps` steps.
std::vector<long> eroded_by_body(Simulation& sim, int steps) {
  for (int i = 0; i < steps; ++i) sim.step();
  std::vector<long> by_body(sim.model().mesh.bodies.size(), 0);
  const State& st = sim.state();
  for (Index i = 0; i < st.particle_count(); ++i)
    ++by_body[static_cast<std::size_t>(sim.model().mesh.tet_body[st.particle_tet[i]])];
  return by_body;
}

}  // namespace

// The limits: k times the smallest l/c of the whole model on every body, or of each body alone.
TEST(Erosion, TheLimitIsAFractionOfTheModelsOrTheBodysOwnFirstStep) {
  const Model at_rest = two_cubes(false, 0.0);
  const std::vector<double> first = smallest_steps(at_rest);
  ASSERT_NEAR(first[1], 4.0 * first[0], 1e-12 * first[1]);  // cells 4 times as large
  for (const bool per_body : {false, true}) {
    SCOPED_TRACE(per_body ? "body" : "model");
    SolverSettings settings;
    settings.end_time = 1.0;
    Simulation sim(two_cubes(per_body, 0.0), settings);
    sim.step();
    const std::vector<double> limit = sim.erosion_steps();
    ASSERT_EQ(limit.size(), 2u);
    for (int b = 0; b < 2; ++b)
      EXPECT_NEAR(limit[b], k_ratio * (per_body ? first[b] : first[0]), 1e-12 * limit[b]) << b;
  }
  SolverSettings settings;
  settings.end_time = 1.0;
  Model off = two_cubes(true, 0.0);
  off.erosion_step_ratio = 0.0;
  Simulation sim(std::move(off), settings);
  sim.step();
  EXPECT_TRUE(sim.erosion_steps().empty());
}

// The coarse cube compressed so fast that the bulk viscosity takes its cells' step below half
// their own first step, yet far above half the fine cube's: they erode under the body's
// reference, none under the model's; the fine cube, at rest, keeps every cell either way.
TEST(Erosion, ACompressedCoarseBodyErodesBelowItsOwnFirstStep) {
  // The coarse cells' l = 0.71 × 4 mm and |ε̇v| = 3 × 7e5/s: Q = C1 c + C2 l |ε̇v| = 1.6 c, and
  // their step l / (Q + √(Q² + c²)) is 0.29 l/c, below half their own first step (0.5 l/c),
  // above half the fine cube's (0.125 l/c).
  const double rate = 7e5;
  SolverSettings settings;
  settings.end_time = 1.0;
  Simulation by_model(two_cubes(false, rate), settings);
  Simulation by_body(two_cubes(true, rate), settings);
  const std::vector<long> model_eroded = eroded_by_body(by_model, 3);
  const std::vector<long> body_eroded = eroded_by_body(by_body, 3);
  EXPECT_EQ(model_eroded[0], 0);
  EXPECT_EQ(model_eroded[1], 0);
  EXPECT_EQ(body_eroded[0], 0);
  EXPECT_GT(body_eroded[1], 0);
  EXPECT_EQ(by_body.conversions()->eroded, body_eroded[1]);
}
