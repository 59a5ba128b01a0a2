// The command line: outputs, refusals, exit codes, determinism.
#include <gtest/gtest.h>

#include <filesystem>
#include <regex>

#include "../test_util.hpp"

using namespace tc;
namespace fs = std::filesystem;

namespace {

const std::string k_case = test::source_path("data/cases/elastic-vibration.yaml");
// A short version of the vibration case for CLI tests.
const std::string k_short = "--set end_time=2.0e-5 --set output.interval=1.0e-5";

std::string quote(const std::string& s) {
  return "'" + s + "'";
}

}  // namespace

TEST(Cli, RunWritesSeriesHistoryAndSummary) {
  test::TempDir dir("cli-run");
  const std::string out = dir / "out";
  const auto r = test::run_cli(
      "run " + quote(k_case) + " " + k_short + " --quiet --out " + quote(out), dir.str());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(r.out.empty()) << "--quiet prints nothing: " << r.out;
  EXPECT_TRUE(fs::exists(out + "/case.pvd"));
  EXPECT_TRUE(fs::exists(out + "/frame_0000.vtu"));
  EXPECT_TRUE(fs::exists(out + "/frame_0002.vtu"));  // t = 0, 1e-5, 2e-5
  EXPECT_FALSE(fs::exists(out + "/frame_0003.vtu"));
  const test::Json summary = test::read_json(out + "/summary.json");
  EXPECT_EQ(summary.at("schema"), "tetcontact.summary/1");
  EXPECT_EQ(summary.at("status"), "ok");
  EXPECT_GE(test::number(summary, "/time"), 2.0e-5);
  // One body, no contact: the vibration's balance measured 4.3e-5 (its bound ~10x).
  EXPECT_LT(test::number(summary, "/energy/balance_error_max"), 5e-4);
  EXPECT_LT(test::number(summary, "/momentum/relative_error"), 1e-12);
  for (const char* key :
       {"/wall_seconds", "/modules", "/mesh/surface_faces", "/mesh/surface_edges", "/timings",
        "/energy/contact_work", "/energy/total_initial", "/bodies", "/bodies/0/bbox_min",
        "/contact/node_face", "/contact/edge_edge", "/penetration/max_depth_over_h",
        "/penetration/max_crossings", "/contact/first_time"})
    EXPECT_TRUE(summary.contains(test::Json::json_pointer(key))) << key;
  // History: a header and one row per 10 steps plus the final one.
  const std::string history = test::read_text(out + "/history.csv");
  EXPECT_EQ(history.rfind("step,t,dt,kinetic,internal,", 0), 0u);
  EXPECT_NE(history.find("seconds_elements"), std::string::npos);
  EXPECT_GT(std::count(history.begin(), history.end(), '\n'), 10);
  // No temporary file is left behind.
  for (const auto& e : fs::directory_iterator(out))
    EXPECT_NE(e.path().extension(), ".tmp") << e.path();
}

// A run that ends released (a coarse Taylor rod off its anvil) writes its last frame and history
// row at the time it ended, and says why it ended.
TEST(Cli, ARunEndedReleasedWritesItsLastFrameAndHistoryRow) {
  test::TempDir dir("cli-released");
  const std::string out = dir / "out";
  const auto r =
      test::run_cli("run " + quote(test::source_path("data/cases/taylor.yaml")) +
                        " --set parameters.nc=4 --set parameters.na=12 --out " + quote(out),
                    dir.str());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("(released: nothing pushed since t = "), std::string::npos) << r.out;
  const test::Json summary = test::read_json(out + "/summary.json");
  EXPECT_EQ(summary.at("end").at("by"), "released");
  EXPECT_EQ(test::number(summary, "/end/when_released"), 5.0e-6);
  const double time = test::number(summary, "/time");
  EXPECT_LT(time, 0.5 * test::number(summary, "/end_time"));
  EXPECT_GE(time - test::number(summary, "/end/last_push"), 5.0e-6);
  // The history's last row and the series' last frame are at the end.
  const std::string history = test::read_text(out + "/history.csv");
  const std::size_t last = history.rfind('\n', history.size() - 2) + 1;
  const std::string row = history.substr(last);
  const std::size_t comma = row.find(',');
  EXPECT_EQ(std::stol(row.substr(0, comma)), test::number(summary, "/steps")) << row;
  EXPECT_EQ(std::stod(row.substr(comma + 1)), time) << row;
  const std::string pvd = test::read_text(out + "/case.pvd");
  const std::regex timestep("timestep=\"([^\"]+)\"");
  std::string last_step;
  for (auto it = std::sregex_iterator(pvd.begin(), pvd.end(), timestep);
       it != std::sregex_iterator(); ++it)
    last_step = (*it)[1];
  ASSERT_FALSE(last_step.empty()) << pvd;
  EXPECT_NEAR(std::stod(last_step), time, 1e-12) << pvd;
}

TEST(Cli, FinalTableOnStdout) {
  test::TempDir dir("cli-table");
  const auto r = test::run_cli(
      "run " + quote(k_case) + " " + k_short + " --out " + quote(dir / "o"), dir.str());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("status     ok"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("balance error"), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("progress:"), std::string::npos) << "plain progress lines off a terminal";
}

TEST(Cli, NonEmptyOutputIsRefusedUnlessForced) {
  test::TempDir dir("cli-force");
  const std::string out = dir / "out";
  fs::create_directories(out);
  test::write_text(out + "/notes.txt", "mine");
  test::write_text(out + "/frame_0042.vtu", "stale");
  auto r = test::run_cli("run " + quote(k_case) + " " + k_short + " --quiet --out " + quote(out),
                         dir.str());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("not empty"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out + "/summary.json"));
  r = test::run_cli("run " + quote(k_case) + " " + k_short + " --quiet --force --out " + quote(out),
                    dir.str());
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(out + "/summary.json"));
  EXPECT_TRUE(fs::exists(out + "/notes.txt"));        // not ours: kept
  EXPECT_FALSE(fs::exists(out + "/frame_0042.vtu"));  // a stale frame of ours: removed
}

TEST(Cli, BadInputExitsTwoAndWritesNothing) {
  test::TempDir dir("cli-bad");
  const std::string text = test::read_text(k_case);
  struct Bad {
    std::string args, expect;
  };
  test::write_text(dir / "neg.yaml",
                   std::regex_replace(text, std::regex("density: 2700"), "density: -2700"));
  test::write_text(dir / "syntax.yaml", text + "\nbodies: [\n");
  const std::vector<Bad> cases = {
      {quote(dir / "neg.yaml"), ":17:14: key 'materials.aluminium.density': must be positive"},
      {quote(dir / "syntax.yaml"), "YAML syntax error"},
      {quote(dir / "absent.yaml"), "case file not found"},
      {quote(k_case) + " --set solver.cfl=0", "--set solver.cfl"},
      {quote(k_case) + " --set bodies.0.mesh.box.cells=[40,0,4]", "must be in [1, 4096]"},
      // A misspelt parameter is refused, not added beside the one the case reads.
      {quote(test::source_path("data/cases/whipple.yaml")) + " --set parameters.V=3000",
       "--set parameters.V=3000: the case declares no parameter 'V' (did you mean 'v'?)"},
  };
  for (const Bad& b : cases) {
    const std::string out = dir / "out";
    const auto r = test::run_cli("run " + b.args + " --out " + quote(out), dir.str());
    EXPECT_EQ(r.code, 2) << b.args << "\n" << r.err;
    EXPECT_NE(r.err.find(b.expect), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "one message: " << r.err;
    EXPECT_FALSE(fs::exists(out)) << "nothing written for " << b.args;
    const auto c = test::run_cli("check " + b.args, dir.str());
    EXPECT_EQ(c.code, 2) << b.args;
  }
}

TEST(Cli, InvertedInputElementIsBadInput) {
  test::TempDir dir("cli-inverted");
  // A 2.2 mesh with two tets of opposite orientation: the second is folded.
  test::write_text(dir / "folded.msh",
                   "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n5\n1 0 0 0\n2 1 0 0\n3 0 1 0\n"
                   "4 0 0 1\n5 0.2 0.2 0.5\n$EndNodes\n$Elements\n3\n1 4 0 1 2 3 4\n"
                   "2 4 0 1 2 3 5\n3 4 0 1 3 2 5\n$EndElements\n");
  std::string text = test::read_text(k_case);
  text = std::regex_replace(text, std::regex("box: \\{size: .*\\}"), "file: folded.msh");
  text = std::regex_replace(text, std::regex("    velocity_regions:\\n.*\\n.*\\n"), "");
  test::write_text(dir / "c.yaml", text);
  const auto r =
      test::run_cli("run " + quote(dir / "c.yaml") + " --out " + quote(dir / "out"), dir.str());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("body 'bar', tet 2: inverted element"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "out"));
}

TEST(Cli, RunFailureExitsOneWithStatus) {
  test::TempDir dir("cli-fail");
  // The halves meeting at 200 km/s crush the middle tets within a step: the run stops and
  // says so.
  const auto r = test::run_cli("run " + quote(k_case) +
                                   " --set 'bodies.0.velocity_regions.0.velocity=[1.0e5,0,0]'"
                                   " --set 'bodies.0.velocity_regions.1.velocity=[-1.0e5,0,0]'"
                                   " --quiet --out " +
                                   quote(dir / "o"),
                               dir.str());
  EXPECT_EQ(r.code, 1) << r.err;
  const test::Json summary = test::read_json(dir / "o/summary.json");
  EXPECT_EQ(summary.at("status").get<std::string>().rfind("failed: ", 0), 0u) << summary;
  EXPECT_NE(r.err.find("run failed"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::exists(dir / "o/history.csv"));
}

TEST(Cli, SameCaseGivesBitIdenticalResults) {
  test::TempDir dir("cli-determinism");
  for (const char* o : {"a", "b"}) {
    const auto r = test::run_cli(
        "run " + quote(k_case) + " " + k_short + " --quiet --out " + quote(dir / o), dir.str());
    ASSERT_EQ(r.code, 0) << r.err;
  }
  for (const char* f : {"frame_0000.vtu", "frame_0001.vtu", "frame_0002.vtu", "case.pvd"})
    EXPECT_EQ(test::read_text(dir / ("a/" + std::string(f))),
              test::read_text(dir / ("b/" + std::string(f))))
        << f;
  // history.csv: identical but for the wall-clock stage timings (the last columns).
  auto strip = [](const std::string& csv) {
    std::string out;
    std::istringstream in(csv);
    for (std::string line; std::getline(in, line);) {
      std::size_t commas = 0, cut = line.size();
      for (std::size_t i = 0; i < line.size(); ++i)
        if (line[i] == ',' && ++commas == 11) cut = i;
      out += line.substr(0, cut) + "\n";
    }
    return out;
  };
  EXPECT_EQ(strip(test::read_text(dir / "a/history.csv")),
            strip(test::read_text(dir / "b/history.csv")));
}

TEST(Cli, HelpVersionAndUsageErrors) {
  test::TempDir dir("cli-help");
  auto r = test::run_cli("--version", dir.str());
  EXPECT_EQ(r.code, 0);
  EXPECT_EQ(r.out.rfind("tetcontact ", 0), 0u);
  r = test::run_cli("run --help", dir.str());
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.out.find("--force"), std::string::npos);
  r = test::run_cli("check --help", dir.str());
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.out.find("Usage: tetcontact check [OPTIONS] case"), std::string::npos) << r.out;
  r = test::run_cli("frobnicate", dir.str());
  EXPECT_EQ(r.code, 2);
  r = test::run_cli("run " + quote(k_case) + " --bogus", dir.str());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("not expected: --bogus"), std::string::npos) << r.err;
  r = test::run_cli("check " + quote(k_case), dir.str());
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find(": ok"), std::string::npos);
}

TEST(Cli, CheckFailsWhenAnExpectedBoundIsMissed) {
  test::TempDir dir("cli-expect");
  const std::string c = quote(test::source_path("data/cases/stability/touching-gap0.yaml"));
  auto r = test::run_cli("run " + c + " --check --quiet --out " + quote(dir / "ok"), dir.str());
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(test::read_json(dir / "ok/summary.json").at("expect_pass"), true);
  // A bound no run can hold: the run completes, the summary says so, --check exits 1.
  r = test::run_cli("run " + c + " --check --quiet --set expect.energy_balance=1e-30 --out " +
                        quote(dir / "tight"),
                    dir.str());
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("expected bound"), std::string::npos) << r.err;
  EXPECT_EQ(test::read_json(dir / "tight/summary.json").at("expect_pass"), false);
  // An unknown figure is bad input.
  r = test::run_cli("run " + c + " --quiet --set expect.speed=1 --out " + quote(dir / "bad"),
                    dir.str());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("expect"), std::string::npos) << r.err;
}

TEST(Cli, BodiesOverlappingAtStartAreBadInputUnlessAllowed) {
  test::TempDir dir("cli-overlap");
  const std::string micro = quote(test::source_path("data/cases/micro/coincident-faces.yaml"));
  // The upper box 1 mm into the lower one (they touch exactly as shipped).
  const std::string sunk = " --set 'bodies.1.transform=[{translate: [0, 0, 0.004]}]'";
  auto r = test::run_cli("run " + micro + sunk + " --out " + quote(dir / "out"), dir.str());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("bodies overlap at t = 0"), std::string::npos) << r.err;
  // Node on node: each box's nodes are as deep in the other; the message names one pair.
  EXPECT_TRUE(std::regex_search(r.err, std::regex("a node of '(upper|lower)' 0.001 m inside "
                                                  "'(lower|upper)'")))
      << r.err;
  EXPECT_NE(r.err.find("contact.initial_overlap: allow"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "out"));
  // As shipped (touching), and sunk but allowed, it runs.
  r = test::run_cli("check " + micro, dir.str());
  EXPECT_EQ(r.code, 0) << r.err;
  r = test::run_cli("run " + micro + sunk +
                        " --set contact.initial_overlap=allow --set end_time=1e-7 --quiet --out " +
                        quote(dir / "allowed"),
                    dir.str());
  EXPECT_EQ(r.code, 0) << r.err;
  r = test::run_cli("check " + micro + " --set contact.initial_overlap=sometimes", dir.str());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("initial_overlap must be error or allow"), std::string::npos) << r.err;
}
