// `tetcontact limit`: bracketing the speed at which a ball perforates a plate.
#include <gtest/gtest.h>

#include <algorithm>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "../test_util.hpp"
#include "plate_case.hpp"
#include "tetcontact/io/case.hpp"

using namespace tc;

namespace {

namespace fs = std::filesystem;

struct Line {
  std::string vary, lo, hi, at_lo, at_hi, status, equation_lo, equation_hi;
  int runs = 0, reused = 0;
  double wall_seconds = 0.0, run_seconds = 0.0;
};
// limit.csv's lines, by the header's column names (no field of this test's is quoted).
std::vector<Line> read_limit(const std::string& path, bool vary) {
  std::istringstream in(test::read_text(path));
  const auto fields = [](const std::string& row) {
    std::vector<std::string> f;
    std::stringstream ss(row);
    for (std::string x; std::getline(ss, x, ',');) f.push_back(x);
    return f;
  };
  std::string row;
  std::getline(in, row);
  const std::vector<std::string> header = fields(row);
  std::vector<Line> out;
  while (std::getline(in, row)) {
    const std::vector<std::string> f = fields(row);
    EXPECT_EQ(f.size(), header.size()) << row;
    const auto at = [&](const std::string& name) {
      const auto it = std::find(header.begin(), header.end(), name);
      EXPECT_NE(it, header.end()) << "no column " << name << " in " << path;
      return it == header.end() ? std::string() : f.at(it - header.begin());
    };
    Line l;
    if (vary) l.vary = f[0];
    l.lo = at("lo");
    l.hi = at("hi");
    l.at_lo = at("criterion_lo");
    l.at_hi = at("criterion_hi");
    l.runs = std::stoi(at("runs"));
    l.reused = std::stoi(at("reused"));
    l.wall_seconds = std::stod(at("wall_seconds"));
    l.run_seconds = std::stod(at("run_seconds"));
    l.status = at("status");
    l.equation_lo = at("equation_critical_diameter_lo");
    l.equation_hi = at("equation_critical_diameter_hi");
    out.push_back(l);
  }
  return out;
}

// The folder of the run at LABEL (its name is the label and its inputs' hash).
std::string run_folder(const std::string& group, const std::string& label) {
  std::vector<std::string> found;
  for (const auto& e : fs::directory_iterator(group))
    if (e.path().filename().string().rfind(label + "_", 0) == 0) found.push_back(e.path());
  EXPECT_EQ(found.size(), 1u) << label << " in " << group;
  return found.empty() ? group + "/" + label : found.front();
}

const std::string k_search =
    "--find parameters.v --between 200 4000 --criterion perforated:plate --jobs 2 "
    "--tolerance 0.05";

}  // namespace

// The bracket: not perforated at its lower end, perforated at its upper end, 5 % wide; a
// thicker plate needs a higher speed; every run's summary kept.
TEST(Limit, BracketsThePerforationSpeed) {
  test::TempDir dir("limit");
  test::write_text(dir / "plate.yaml", test::k_plate);
  const auto r =
      test::run_cli("limit '" + dir / "plate.yaml" + "' " + k_search +
                        " --vary parameters.tb=1.0e-3,2.0e-3 --out '" + dir / "out" + "'",
                    dir.str());
  ASSERT_EQ(r.code, 0) << r.err;
  const std::vector<Line> lines = read_limit(dir / "out/limit.csv", true);
  ASSERT_EQ(lines.size(), 2u);
  for (const Line& l : lines) {
    EXPECT_EQ(l.status, "ok");
    EXPECT_EQ(l.at_lo, "0");
    EXPECT_EQ(l.at_hi, "1");
    const double lo = std::stod(l.lo), hi = std::stod(l.hi);
    EXPECT_LT(lo, hi);
    EXPECT_LE(hi - lo, 0.05 * hi);
    const std::string run =
        run_folder(dir / ("out/runs/parameters.tb=" + l.vary), "parameters.v=" + l.lo);
    EXPECT_TRUE(fs::exists(run + "/summary.json"));
    // The run's log holds its table (the search runs it without --quiet).
    EXPECT_NE(test::read_text(run + "/run.log").find("status"), std::string::npos) << run;
    // The search's elapsed time and the runs' own times, apart: two at once, so the search
    // takes less than their sum (each run is seconds; starting one costs milliseconds).
    EXPECT_GT(l.wall_seconds, 0.0);
    EXPECT_LT(l.wall_seconds, l.run_seconds);
    // Christiansen's critical diameter beside the bracket, for the shots at its two ends.
    for (const auto& [v, written] : {std::pair{l.lo, l.equation_lo}, {l.hi, l.equation_hi}}) {
      const Case c =
          load_case(dir / "plate.yaml", {"parameters.tb=" + l.vary, "parameters.v=" + v});
      EXPECT_NEAR(std::stod(written), christiansen_critical_diameter(c.shield_equation.shot),
                  1e-8 * std::stod(written))
          << v;
    }
    EXPECT_GT(std::stod(l.equation_lo), std::stod(l.equation_hi));  // faster: a smaller sphere
  }
  EXPECT_GE(std::stod(lines[0].lo), 1000.0);  // 1 mm: from between 1,000 and 1,400 m/s
  EXPECT_LE(std::stod(lines[0].hi), 1400.0);
  EXPECT_GT(std::stod(lines[1].lo), std::stod(lines[0].hi));  // 2 mm: higher
  // Bad input: a criterion the case does not measure; nothing run.
  const auto bad = test::run_cli("limit '" + dir / "plate.yaml" +
                                     "' --find parameters.v --between 200 4000 --criterion "
                                     "perforated:ball --out '" +
                                     dir / "bad" + "'",
                                 dir.str());
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.err.find("measure: perforated and body: ball"), std::string::npos) << bad.err;
  EXPECT_FALSE(fs::exists(dir / "bad/runs"));
}

// Killed after some runs had finished (the whole process group, runs included), the search
// resumes: the finished runs are read, not run again, and the bracket is the one an
// uninterrupted search finds (runs are deterministic).
TEST(Limit, ResumesAfterAKill) {
  test::TempDir dir("limit-resume");
  test::write_text(dir / "plate.yaml", test::k_plate);
  const std::string cmd = "limit '" + dir / "plate.yaml" + "' " + k_search + " --quiet --out '";
  const auto whole = test::run_cli(cmd + dir / "whole" + "'", dir.str());
  ASSERT_EQ(whole.code, 0) << whole.err;
  const Line expected = read_limit(dir / "whole/limit.csv", false).at(0);
  // Start the search in its own process group, wait for 3 finished runs, kill the group.
  const std::string out = dir / "killed";
  const std::string script =
      "setsid '" + std::string(TETCONTACT_BINARY) + "' " + cmd + out +
      "' >/dev/null 2>&1 & pid=$!; for i in $(seq 1 600); do "
      "n=$(find '" +
      out +
      "' -name summary.json 2>/dev/null | wc -l); "
      "[ \"$n\" -ge 3 ] && break; sleep 0.05; done; kill -9 -- -$pid; wait $pid 2>/dev/null; true";
  ASSERT_EQ(std::system(("bash -c \"" +
                         [&] {
                           std::string s;
                           for (char c : script)
                             s += c == '"' || c == '$' ? std::string("\\") + c : std::string(1, c);
                           return s;
                         }() +
                         "\"")
                            .c_str()),
            0);
  ASSERT_FALSE(fs::exists(out + "/limit.csv"));  // killed before the end
  const auto resumed = test::run_cli(cmd + out + "'", dir.str());
  ASSERT_EQ(resumed.code, 0) << resumed.err;
  const Line l = read_limit(out + "/limit.csv", false).at(0);
  EXPECT_EQ(l.lo, expected.lo);
  EXPECT_EQ(l.hi, expected.hi);
  EXPECT_EQ(l.runs, expected.runs);
  EXPECT_GE(l.reused, 3);  // the runs finished before the kill
  EXPECT_LT(l.reused, l.runs);
}

// A run killed within a search (its case writing checkpoints) goes on from its newest checkpoint
// when the search is run again: the same bracket, that run's summary the figures of the run never
// interrupted.
TEST(Limit, AKilledRunGoesOnFromItsCheckpoint) {
  test::TempDir dir("limit-checkpoint");
  test::write_text(dir / "plate.yaml", test::k_plate);
  const std::string cmd = "limit '" + dir / "plate.yaml" + "' " + k_search +
                          " --quiet --set output.checkpoint.steps=20 --out '";
  const auto whole = test::run_cli(cmd + dir / "whole" + "'", dir.str());
  ASSERT_EQ(whole.code, 0) << whole.err;
  const Line expected = read_limit(dir / "whole/limit.csv", false).at(0);
  // Every run killed at step 150: the first at 200 m/s ends before it, the one at 4,000 m/s not.
  setenv("TETCONTACT_KILL_AT_STEP", "150", 1);
  const auto killed = test::run_cli(cmd + dir / "out" + "'", dir.str());
  unsetenv("TETCONTACT_KILL_AT_STEP");
  EXPECT_EQ(killed.code, 1) << killed.err;
  const std::string cut = run_folder(dir / "out/runs/all", "parameters.v=4000");
  ASSERT_TRUE(fs::exists(cut + "/checkpoints/step_0000000140.ckpt"));
  ASSERT_FALSE(fs::exists(cut + "/summary.json"));
  const auto resumed = test::run_cli(cmd + dir / "out" + "'", dir.str());
  ASSERT_EQ(resumed.code, 0) << resumed.err;
  const Line l = read_limit(dir / "out/limit.csv", false).at(0);
  EXPECT_EQ(l.lo, expected.lo);
  EXPECT_EQ(l.hi, expected.hi);
  EXPECT_EQ(l.runs, expected.runs);
  EXPECT_NE(test::read_text(cut + "/run.log").find("restarting from"), std::string::npos);
  auto figures = [](test::Json s) {
    for (const char* k : {"wall_seconds", "timings", "restarts"}) s.erase(k);
    return s;
  };
  EXPECT_EQ(figures(test::read_json(cut + "/summary.json")),
            figures(test::read_json(run_folder(dir / "whole/runs/all", "parameters.v=4000") +
                                    "/summary.json")));
  EXPECT_FALSE(fs::exists(cut + "/checkpoints"));
}

// A search run again into the same folder with another --set, or by another build of the program,
// runs anew: its runs are keyed by every input, so none of the 1 mm plate's runs stands for the
// 2 mm plate's (the bracket is the 2 mm plate's, higher), and the first search's runs stay as
// they were.
TEST(Limit, AnotherOverrideIsNeverReused) {
  test::TempDir dir("limit-reuse");
  test::write_text(dir / "plate.yaml", test::k_plate);
  const std::string cmd =
      "limit '" + dir / "plate.yaml" + "' " + k_search + " --quiet --out '" + dir / "out" + "'";
  const auto first = test::run_cli(cmd, dir.str());
  ASSERT_EQ(first.code, 0) << first.err;
  const Line thin = read_limit(dir / "out/limit.csv", false).at(0);
  const auto again = test::run_cli(cmd, dir.str());  // the same inputs: every run read back
  ASSERT_EQ(again.code, 0) << again.err;
  EXPECT_EQ(read_limit(dir / "out/limit.csv", false).at(0).reused, thin.runs);
  // Another build of the program (here the same one with a byte appended, which the loader
  // ignores) is another input: it runs every point anew, beside the first build's runs.
  const std::string other = dir / "other-build";
  fs::copy_file(TETCONTACT_BINARY, other);
  std::ofstream(other, std::ios::app | std::ios::binary) << '\n';
  fs::permissions(other, fs::perms::owner_exec, fs::perm_options::add);
  const std::string other_cmd = "TETCONTACT_DATA='" + test::source_path("data") + "' '" + other +
                                "' " + cmd + " >'" + dir / "other.log" + "' 2>&1";
  ASSERT_EQ(std::system(other_cmd.c_str()), 0) << test::read_text(dir / "other.log");
  const Line rebuilt = read_limit(dir / "out/limit.csv", false).at(0);
  EXPECT_EQ(rebuilt.reused, 0);
  EXPECT_EQ(rebuilt.lo, thin.lo);  // the same code: the same bracket
  EXPECT_EQ(rebuilt.hi, thin.hi);
  const auto thick = test::run_cli(cmd + " --set parameters.tb=2.0e-3", dir.str());
  ASSERT_EQ(thick.code, 0) << thick.err;
  const Line l = read_limit(dir / "out/limit.csv", false).at(0);
  EXPECT_EQ(l.reused, 0);
  EXPECT_GT(std::stod(l.lo), std::stod(thin.hi));
  // A misspelt parameter is refused before any run.
  const auto typo = test::run_cli("limit '" + dir / "plate.yaml" +
                                      "' --find parameters.V --between 200 4000 --criterion "
                                      "perforated:plate --out '" +
                                      dir / "typo" + "'",
                                  dir.str());
  EXPECT_EQ(typo.code, 2);
  EXPECT_NE(typo.err.find("no parameter 'V' (did you mean 'v'?)"), std::string::npos) << typo.err;
  EXPECT_FALSE(fs::exists(dir / "typo"));
}

// --check: every case the search starts from checked as `check` does, nothing run or written; a
// value that makes a bad case is named.
TEST(Limit, CheckChecksEachCaseOfTheSearchAndRunsNothing) {
  test::TempDir dir("limit-check");
  test::write_text(dir / "plate.yaml", test::k_plate);
  const std::string cmd = "limit '" + dir / "plate.yaml" +
                          "' --find parameters.v --between 200 4000 --criterion perforated:plate "
                          "--vary parameters.tb=1.0e-3,2.0e-3 --check --out '" +
                          dir / "out" + "'";
  const auto ok = test::run_cli(cmd, dir.str());
  ASSERT_EQ(ok.code, 0) << ok.err;
  EXPECT_NE(ok.out.find("limit: 4 cases checked"), std::string::npos) << ok.out;
  EXPECT_EQ(std::count(ok.out.begin(), ok.out.end(), '\n'), 5) << ok.out;  // 4 cases, 1 total
  EXPECT_FALSE(fs::exists(dir / "out"));
  const auto bad = test::run_cli(cmd + " --set end_time=-1", dir.str());
  EXPECT_EQ(bad.code, 2) << bad.err;
  EXPECT_FALSE(fs::exists(dir / "out"));
}
