// From case to model: the impact Mach number warnings of the paper's model ranges.
#include <gtest/gtest.h>

#include "../test_util.hpp"
#include "tetcontact/app/setup.hpp"

using namespace tc;

namespace {

const char* k_two_bodies = R"(end_time: 1.0e-6
materials:
  al_linear: {density: 2700, youngs_modulus: 70.0e9, poisson_ratio: 0.3}
  al_mg: {from: al6061-t6}
bodies:
  - name: target
    material: al_linear
    mesh: {box: {size: [0.01, 0.01, 0.01], cells: [1, 1, 1], split: 5}}
  - name: impactor
    material: al_mg
    mesh: {box: {size: [0.01, 0.01, 0.01], cells: [1, 1, 1], split: 5}}
    transform: [{translate: [0, 0, 0.02]}]
    velocity: [0, 0, -1000]
)";

std::vector<std::string> warnings_for(const std::vector<std::string>& overrides,
                                      bool notes = false) {
  test::TempDir dir(notes ? "setup-regime" : "setup-mach");  // tests may run at once
  test::write_text(dir / "c.yaml", k_two_bodies);
  const Case c = load_case(dir / "c.yaml", overrides);
  return notes ? regime_notes(c, build_model(c)) : mach_warnings(c, build_model(c));
}

}  // namespace

// C0 = sqrt(K/ρ): 6,080 m/s for the linear aluminium (K = 100 GPa), 5,240 m/s (c0) for the
// Mie–Grüneisen one.
TEST(Setup, MachWarningsFollowThePapersModelRanges) {
  // 1 km/s: M0 = 0.16 and 0.19, inside every range.
  EXPECT_TRUE(warnings_for({}).empty());
  // 5 km/s: the linear-EOS target at M0 = 0.82 > 0.75 is warned; the Mie–Grüneisen impactor
  // at M0 = 0.95 is inside its 0.75–1.5 range.
  auto w = warnings_for({"bodies.1.velocity=[0,0,-5000]"});
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].find("body 'target'"), std::string::npos) << w[0];
  EXPECT_NE(w[0].find("mie_gruneisen"), std::string::npos) << w[0];
  // 9 km/s: both beyond 1.5.
  w = warnings_for({"bodies.1.velocity=[0,0,-9000]"});
  ASSERT_EQ(w.size(), 2u);
  for (const std::string& s : w)
    EXPECT_NE(s.find("beyond the paper's models"), std::string::npos) << s;
  // Against a wall: the impactor's speed along the wall normal counts.
  w = warnings_for({"bodies.1.velocity=[0,0,-9000]", "walls=[{point: [0,0,-1], normal: [0,0,1]}]",
                    "bodies.0.velocity=[0,0,-9000]"});
  EXPECT_EQ(w.size(), 2u);  // both against the wall; none between the co-moving bodies
}

// The regime a run states: 0.75 < M0 < 1.5 with a Mie–Grüneisen EOS — the impactor
// at 5 km/s (M0 = 0.95), not at 1 km/s (inside the elastic-plastic range) nor at 9 km/s (beyond:
// warned instead), and not the linear-EOS target (warned).
TEST(Setup, RegimeNotesStateTheHydrodynamicRange) {
  EXPECT_TRUE(warnings_for({}, true).empty());
  const auto n = warnings_for({"bodies.1.velocity=[0,0,-5000]"}, true);
  ASSERT_EQ(n.size(), 1u);
  EXPECT_NE(n[0].find("body 'impactor'"), std::string::npos) << n[0];
  EXPECT_NE(n[0].find("hydrodynamic range"), std::string::npos) << n[0];
  EXPECT_NE(n[0].find("vaporisation"), std::string::npos) << n[0];
  EXPECT_TRUE(warnings_for({"bodies.1.velocity=[0,0,-9000]"}, true).empty());
  // Two bodies of one material are one pair and one statement, not one per body.
  const auto both =
      warnings_for({"bodies.1.velocity=[0,0,-5000]", "bodies.0.material=al_mg"}, true);
  ASSERT_EQ(both.size(), 1u);
  EXPECT_NE(both[0].find("bodies 'target' and 'impactor'"), std::string::npos) << both[0];
}

// Symmetry planes at setup: a body cut along a plane without a node layer there, a motion
// across a plane, a body wholly behind a plane, and a malformed plane each stop the setup with
// the file and key; a valid quarter holds its plane nodes and gets a wall per plane.
TEST(Setup, SymmetryPlanesAreCheckedAndBecomeAConstraintAndAWall) {
  test::TempDir dir("setup-symmetry");
  test::write_text(dir / "c.yaml", k_two_bodies);
  const auto error = [&](const std::vector<std::string>& overrides) {
    try {
      const Case c = load_case(dir / "c.yaml", overrides);
      build_model(c);
    } catch (const std::exception& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string even = "bodies.0.mesh.box.cells=[2, 2, 1]";
  const std::string even1 = "bodies.1.mesh.box.cells=[2, 2, 1]";
  EXPECT_NE(error({"symmetry=[x]"}).find("straddles the symmetry plane x = 0"), std::string::npos);
  EXPECT_NE(error({"symmetry=[x]", even, even1, "bodies.1.velocity=[5, 0, -1000]"})
                .find("key 'symmetry': body 'impactor' starts with a velocity of 5 m/s across"),
            std::string::npos);
  EXPECT_NE(
      error({"symmetry=[{axis: x, at: 1.0}]"})
          .find("body 'target': no tet lies on the positive side of the symmetry plane x = 1"),
      std::string::npos);
  EXPECT_NE(error({"symmetry=[w]"}).find("key 'symmetry.0': a symmetry plane is x, y or z"),
            std::string::npos);
  EXPECT_NE(error({"symmetry=[x, x]"}).find("a second symmetry plane normal to x"),
            std::string::npos);

  const Case c = load_case(dir / "c.yaml", {"symmetry=[x, y]", even, even1});
  const Model m = build_model(c);
  ASSERT_EQ(m.walls.size(), 2u);
  EXPECT_EQ(m.walls[0].name, "symmetry-x");
  EXPECT_EQ(m.walls[1].normal, Vec3(0, 1, 0));
  ASSERT_EQ(m.constraints.size(), 2u);
  // Each box of 2 × 2 × 1 cells keeps one cell: its nodes at x = 0 are 2 × 2 of its 8.
  EXPECT_EQ(m.constraints[0].nodes.size(), 8u);
  EXPECT_EQ(m.constraints[0].components, (std::array<bool, 3>{true, false, false}));
  for (const Index n : m.constraints[0].nodes) EXPECT_EQ(m.mesh.x[n].x(), 0.0);
}
