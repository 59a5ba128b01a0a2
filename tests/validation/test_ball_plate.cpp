// The paper's ball through the plate (Dobritsa et al., Fig. 5) on a coarse mesh: perforation, the
// ball's residual speed between the plug-momentum bound and the impact speed, particles from
// both bodies, and the conversions' conservation (as the fracture design asks).
#include <gtest/gtest.h>

#include <cmath>

#include "../test_util.hpp"
#include "tetcontact/app/setup.hpp"
#include "tetcontact/diagnostics/balance.hpp"
#include "tetcontact/diagnostics/penetration.hpp"
#include "tetcontact/diagnostics/reference.hpp"
#include "tetcontact/io/case.hpp"
#include "tetcontact/solver/run_loop.hpp"
#include "tetcontact/solver/simulation.hpp"

using namespace tc;

// Ball 8 cells across, plate 24 × 24 × 2 cells (the case has 16 and 60 × 60 × 3), to 12.5 µs.
TEST(Validation, BallPerforatesPlateAndConversionsConserve) {
  const Case c =
      load_case(test::source_path("data/cases/ball-plate.yaml"),
                {"bodies.0.mesh.sphere.cells_across=8", "bodies.1.mesh.box.cells=[24,24,2]"});
  Simulation sim(build_model(c), solver_settings(c));
  ASSERT_EQ(run_to_end(sim), "ok");
  const Model& model = sim.model();
  const State& st = sim.state();

  // Conservation through every conversion.
  const Sample &first = sim.first_sample(), &last = sim.last_sample();
  EXPECT_LT(std::abs(last.mass - first.mass), 1e-13 * first.mass);
  EXPECT_LT(momentum_error(first, last), 1e-13);  // 1.5e-15 measured
  EXPECT_LT(sim.balance_error_max(), 4e-4);       // 3.5e-5 measured
  ASSERT_NE(sim.conversions(), nullptr);
  EXPECT_LT(sim.conversions()->momentum_error, 1e-14);
  for (const Vec3& x : st.x) ASSERT_TRUE(x.allFinite());

  // Particles from both bodies.
  long from[2] = {0, 0};
  for (Index i = 0; i < st.particle_count(); ++i) ++from[model.mesh.tet_body[st.particle_tet[i]]];
  EXPECT_GT(from[0], 0);
  EXPECT_GT(from[1], 0);

  // The ball's residual speed within the case's bracket: above the plug-momentum bound
  // 2000 m_ball / (m_ball + ρ_Al π R² h) = 1901 m/s (the case file's derivation), below
  // 1975 m/s (a ball that passes without contact keeps 2000 m/s); 1928.9 m/s measured.
  const std::vector<BodyStats> bodies = body_stats(model, st);
  const double v = -bodies[0].velocity.z();
  EXPECT_LT(v, 1975.0);
  EXPECT_GT(v, 1901.0);
  const std::vector<ReferenceResult> refs =
      evaluate_references(c.references, model, st, sim.run_figures());
  ASSERT_EQ(refs.size(), 2u);
  EXPECT_TRUE(refs[0].pass) << refs[0].measured;

  // A hole: no plate cell centred in the plate's original layer within half the ball's radius
  // of the axis, and the ball below the plate.
  double hole = 1.0;
  const BodyRange& plate = model.mesh.bodies[1];
  for (Index t = plate.tet_begin; t < plate.tet_end; ++t) {
    if (st.damage[t] == Damage::particle) continue;
    Vec3 centre = Vec3::Zero();
    for (Index k : model.mesh.tets[t]) centre += 0.25 * st.x[k];
    if (centre.z() < -2e-3 || centre.z() > 0.0) continue;
    hole = std::min(hole, centre.head<2>().norm());
  }
  EXPECT_GT(hole, 0.5e-2);
  EXPECT_LT(bodies[0].bbox_min.z(), -2e-3 - 1e-2);

  // No particle inside a body at the end (the penetration diagnostics' exact test).
  PenetrationProbe probe(model);
  EXPECT_EQ(probe.measure(st).particles_inside, 0);
}

// The residual-speed reference must exclude the answer of a run without contact: the ball then
// keeps its 2000 m/s at any time (2 µs here, on the coarse mesh), and the reference fails.
TEST(Validation, BallPlateReferenceFailsWithoutContact) {
  const Case c =
      load_case(test::source_path("data/cases/ball-plate.yaml"),
                {"bodies.0.mesh.sphere.cells_across=8", "bodies.1.mesh.box.cells=[24,24,2]",
                 "contact.enabled=false", "end_time=2.0e-6"});
  Simulation sim(build_model(c), solver_settings(c));
  ASSERT_EQ(run_to_end(sim), "ok");
  const std::vector<ReferenceResult> refs =
      evaluate_references(c.references, sim.model(), sim.state(), sim.run_figures());
  ASSERT_EQ(refs.size(), 2u);
  EXPECT_EQ(refs[0].spec->name, "ball residual velocity");
  EXPECT_NEAR(refs[0].measured, -2000.0, 1e-3);
  EXPECT_FALSE(refs[0].pass);
}
