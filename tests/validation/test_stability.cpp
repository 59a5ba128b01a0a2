// The stability suite (data/cases/stability/, each case a ctest of its own with --check) must
// be able to fail: every case with contact states penetration bounds near what it measures,
// and run with contact switched off it misses them while the run itself completes.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include "../test_util.hpp"
#include "tetcontact/io/case.hpp"

using namespace tc;

TEST(StabilitySuite, EveryContactCaseFailsItsBoundsWithContactOff) {
  namespace fs = std::filesystem;
  const fs::path dir = test::source_path("data/cases/stability");
  std::vector<fs::path> cases;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".yaml") cases.push_back(e.path());
  std::sort(cases.begin(), cases.end());
  ASSERT_GE(cases.size(), 11u) << "the suite's cases are missing from " << dir;
  long with_contact = 0;
  for (const fs::path& f : cases) {
    SCOPED_TRACE(f.filename().string());
    const Case c = load_case(f.string());
    if (!c.contact) continue;
    ++with_contact;
    // A penetration bound is what contact is checked by; momentum and energy hold without it.
    const auto bound = std::find_if(c.expect.begin(), c.expect.end(),
                                    [](const auto& e) { return e.first == "max_depth_over_h"; });
    ASSERT_NE(bound, c.expect.end()) << "a contact case without a penetration bound";
    test::TempDir tmp("stability-off-" + f.stem().string());
    const auto r =
        test::run_cli("run '" + f.string() +
                          "' --check --quiet --set contact.enabled=false --out '" + tmp / "o" + "'",
                      tmp.str());
    EXPECT_EQ(r.code, 1) << r.err;
    const test::Json s = test::read_json(tmp / "o/summary.json");
    EXPECT_EQ(s.at("status"), "ok");  // the run completed: it is the check that fails
    EXPECT_EQ(s.at("expect_pass"), false);
    bool depth_failed = false;
    for (const test::Json& e : s.at("expect"))
      if (e.at("name") == "max_depth_over_h") depth_failed = e.at("pass") == false;
    EXPECT_TRUE(depth_failed) << s.at("expect");
  }
  EXPECT_EQ(with_contact, 10);  // all but the spinning body
}
