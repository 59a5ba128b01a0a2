// Reference measures: the hole diameter of a plate with its central cells gone, and a measure
// without a reference value (reported, not judged).
#include <gtest/gtest.h>

#include <cmath>

#include "../solver/solver_fixture.hpp"
#include "tetcontact/diagnostics/reference.hpp"
#include "tetcontact/solver/simulation.hpp"

using namespace tc;

TEST(Reference, HoleDiameterAfterTheCentralCellsAreGone) {
  // A plate 4 × 4 × 1 of unit hexes, x and y from −2 to 2.
  TetMesh plate = make_box(Vec3(4, 4, 1), {4, 4, 1}, HexSplit::six);
  Model model = test::single_body_model(plate, test::aluminium());
  State st = initial_state(model);
  ReferenceSpec hole;
  hole.name = "hole";
  hole.measure = ReferenceSpec::Measure::hole_diameter;
  hole.body = "body";
  hole.axis = 2;
  hole.region_min = Vec3(-2, -2, -1);
  hole.region_max = Vec3(2, 2, 1);
  hole.value = hole.tolerance = std::nan("");
  auto r = evaluate_references({hole}, model, st);
  ASSERT_TRUE(r[0].error.empty()) << r[0].error;
  // A tet centre of a central hex lies 0.25–0.75 from its sides: within 0.75 √2 of the axis.
  EXPECT_LT(r[0].measured, 2.0 * 0.75 * std::sqrt(2.0));
  EXPECT_FALSE(r[0].judged);
  EXPECT_TRUE(r[0].pass);
  EXPECT_TRUE(std::isnan(r[0].relative_error));
  // The four central hexes (|x|, |y| < 1) turned into particles: every remaining centre lies
  // outside that square, a tet centre of a unit hex within 0.25–0.75 of its sides.
  for (Index t = 0; t < model.mesh.tet_count(); ++t) {
    Vec3 c = Vec3::Zero();
    for (Index k : model.mesh.tets[t]) c += 0.25 * model.mesh.x[k];
    if (std::abs(c.x()) < 1 && std::abs(c.y()) < 1) st.damage[t] = Damage::particle;
  }
  r = evaluate_references({hole}, model, st);
  EXPECT_GT(r[0].measured, 2.0 * 1.25);
  EXPECT_LT(r[0].measured, 2.0 * std::hypot(1.75, 0.75));
  // Judged: a reference value makes it pass or fail.
  hole.value = 3.0;
  hole.tolerance = 1e-6;
  r = evaluate_references({hole}, model, st);
  EXPECT_TRUE(r[0].judged);
  EXPECT_EQ(r[0].pass, std::abs(r[0].measured - 3.0) <= 3e-6);
}
