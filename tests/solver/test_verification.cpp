// The step verification in the solver (issue 15): with it, the paper's cubes read 0 crossings
// and 0 nodes inside at every step even with edge–edge contact off, which without it lets the
// edges through; momentum holds; the zones' work is reported.
#include <gtest/gtest.h>

#include "../test_util.hpp"

using namespace tc;

TEST(Verification, CubesWithoutEdgeContactStayIntersectionFreeEveryStep) {
  test::TempDir dir("verification-cubes");
  const std::string base = "run '" + test::source_path("data/cases/cubes-edge.yaml") +
                           "' --quiet --set contact.edge_edge=false "
                           "--set diagnostics.every_step=true";
  auto r =
      test::run_cli(base + " --set contact.verify=false --out '" + dir / "off" + "'", dir.str());
  ASSERT_EQ(r.code, 0) << r.err;
  const test::Json off = test::read_json(dir / "off/summary.json");
  EXPECT_GT(test::number(off, "/penetration/max_crossings"), 0);  // the edges pass through
  EXPECT_TRUE(off.at("contact").at("verification").is_null());

  r = test::run_cli(base + " --set contact.verify=true --out '" + dir / "on" + "'", dir.str());
  ASSERT_EQ(r.code, 0) << r.err;
  const test::Json on = test::read_json(dir / "on/summary.json");
  EXPECT_EQ(on.at("penetration").at("measured_at"), "every step");
  EXPECT_GT(test::number(on, "/penetration/samples"), 20);
  EXPECT_EQ(test::number(on, "/penetration/max_crossings"), 0);
  EXPECT_EQ(test::number(on, "/penetration/max_nodes_inside"), 0);
  EXPECT_LT(test::number(on, "/momentum/relative_error"), 1e-12);
  const test::Json& v = on.at("contact").at("verification");
  EXPECT_GT(test::number(v, "/pairs_checked"), 0);
  EXPECT_GT(test::number(v, "/failed_after_passes"), 0);  // the edge pairs contact missed
  EXPECT_GT(test::number(v, "/impact_zones"), 0);
  EXPECT_EQ(test::number(v, "/unresolved_steps"), 0);
  // The history has the penetration of every step: all zeros.
  const std::string history = test::read_text(dir / "on/history.csv");
  EXPECT_NE(history.find(",nodes_inside,crossings"), std::string::npos);
}
