// Every shipped case with contact must fail its own checks (its `expect` bounds and its
// references, `run --check`) when run with contact switched off: a check that holds without
// contact does not check contact. The heavier cases run on their test meshes, or shorter: the
// answer without contact (bodies passing through each other, no contact force) is wrong at any
// mesh and from the first contact on.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <map>

#include "../test_util.hpp"
#include "tetcontact/io/case.hpp"

using namespace tc;

TEST(ContactOff, EveryShippedContactCaseFailsItsChecks) {
  namespace fs = std::filesystem;
  const std::map<std::string, std::string> lighter = {
      {"ball-plate",
       "--set bodies.0.mesh.sphere.cells_across=8 --set 'bodies.1.mesh.box.cells=[24,24,2]' "
       "--set end_time=2.0e-6"},
      {"cylinders",
       "--set bodies.0.mesh.cylinder.cells_across=8 --set bodies.0.mesh.cylinder.cells_axial=8 "
       "--set bodies.1.mesh.cylinder.cells_across=4 --set bodies.1.mesh.cylinder.cells_axial=4"},
      {"hertz-spheres",
       "--set end_time=10.0e-6 --set bodies.0.mesh.sphere.growth=0.3 "
       "--set bodies.1.mesh.sphere.growth=0.3 --set bodies.0.mesh.sphere.cell_size=1.0e-3 "
       "--set bodies.1.mesh.sphere.cell_size=1.0e-3"},
      {"whipple",
       "--set parameters.hb=1.0e-3 --set parameters.hw=2.0e-3 --set parameters.np=6 "
       "--set parameters.wb=16e-3 --set parameters.end=3.0e-6"},
      {"taylor-symmetric",
       "--set end_time=10.0e-6 --set bodies.0.mesh.cylinder.cells_across=6 "
       "--set bodies.0.mesh.cylinder.cells_axial=30 --set bodies.1.mesh.cylinder.cells_across=6 "
       "--set bodies.1.mesh.cylinder.cells_axial=30"},
  };
  std::vector<fs::path> cases;
  for (const auto& e : fs::directory_iterator(test::source_path("data/cases")))
    if (e.path().extension() == ".yaml") cases.push_back(e.path());
  std::sort(cases.begin(), cases.end());
  std::vector<std::string> checked;
  for (const fs::path& f : cases) {
    const std::string name = f.stem().string();
    SCOPED_TRACE(name);
    const Case c = load_case(f.string());
    if (!c.contact) continue;
    ASSERT_FALSE(c.expect.empty() && c.references.empty()) << "a contact case with no checks";
    checked.push_back(name);
    const auto it = lighter.find(name);
    test::TempDir tmp("contact-off-" + name);
    const auto r = test::run_cli("run '" + f.string() + "' --check --quiet --force " +
                                     (it == lighter.end() ? "" : it->second) +
                                     " --set contact.enabled=false --out '" + tmp / "o" + "'",
                                 tmp.str());
    EXPECT_EQ(r.code, 1) << r.err;
    const test::Json s = test::read_json(tmp / "o/summary.json");
    EXPECT_EQ(s.at("status"), "ok");  // the run completed: it is the check that fails
    const bool expect_failed = s.contains("expect_pass") && s.at("expect_pass") == false;
    const bool refs_failed = s.contains("references_pass") && s.at("references_pass") == false;
    EXPECT_TRUE(expect_failed || refs_failed) << s.dump(2);
  }
  const std::vector<std::string> all = {"ball-plate",      "bars-impact",      "cubes-edge",
                                        "cylinders",       "hertz-spheres",    "spall-plate",
                                        "staggered-patch", "taylor-symmetric", "whipple"};
  EXPECT_EQ(checked, all);
}
