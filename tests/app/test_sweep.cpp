// `tetcontact sweep`: one row per combination, the error against the case's references (the
// largest of them) or against the finest run, refusals of bad input, and the plot tool.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <sstream>

#include "../test_util.hpp"
#include "tetcontact/app/sweep.hpp"

using namespace tc;
namespace fs = std::filesystem;

namespace {

std::vector<std::vector<std::string>> read_csv(const std::string& path) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(test::read_text(path));
  std::string line;
  while (std::getline(in, line)) {
    std::vector<std::string> row(1);
    bool quoted = false;
    for (char ch : line) {
      if (ch == '"')
        quoted = !quoted;
      else if (ch == ',' && !quoted)
        row.emplace_back();
      else
        row.back() += ch;
    }
    rows.push_back(row);
  }
  return rows;
}

std::size_t column(const std::vector<std::string>& header, const std::string& name) {
  return static_cast<std::size_t>(std::find(header.begin(), header.end(), name) - header.begin());
}

const std::string k_bars = "'" + test::source_path("data/cases/bars-impact.yaml") + "'";
const std::string k_mesh =
    " --vary 'bodies.0.mesh.box.cells+bodies.1.mesh.box.cells=[10,1,1],[20,2,2]'";

// Runs a sweep of the bars with `options`; returns its sweep.csv (fails the test otherwise).
// `folder` names its own scratch folder: ctest runs tests in parallel.
std::vector<std::vector<std::string>> sweep_bars(const std::string& folder,
                                                 const std::string& options) {
  test::TempDir dir(folder);
  const auto r = test::run_cli(
      "sweep " + k_bars + k_mesh + " " + options + " --quiet --out " + dir.str() + "/out",
      dir.str());
  EXPECT_EQ(r.code, 0) << r.err;
  return read_csv(dir.str() + "/out/sweep.csv");
}

}  // namespace

TEST(Sweep, SplitsValuesOutsideBrackets) {
  EXPECT_EQ(split_values("1,2,3"), (std::vector<std::string>{"1", "2", "3"}));
  EXPECT_EQ(split_values("[1,2],{a: 1, b: 2},x"),
            (std::vector<std::string>{"[1,2]", "{a: 1, b: 2}", "x"}));
}

TEST(Sweep, OneRowPerCombinationWithTheLargestReferenceError) {
  const auto rows = sweep_bars("sweep-rows", "--vary contact.passes=1,3");
  ASSERT_EQ(rows.size(), 5u);  // header and 2 × 2 runs
  const auto& h = rows[0];
  EXPECT_EQ(rows[1][column(h, "contact.passes")], "1");  // the last key varies fastest
  EXPECT_EQ(rows[2][column(h, "contact.passes")], "3");
  EXPECT_EQ(rows[3][column(h, "bodies.0.mesh.box.cells+bodies.1.mesh.box.cells")], "[20,2,2]");
  for (std::size_t i = 1; i < rows.size(); ++i) {
    const auto& row = rows[i];
    EXPECT_EQ(row[column(h, "status")], "ok");
    double largest = 0.0;
    int refs = 0;
    for (std::size_t c = 0; c < h.size(); ++c)
      if (h[c].rfind("error:", 0) == 0)
        largest = std::max(largest, std::abs(std::stod(row[c]))), ++refs;
    EXPECT_EQ(refs, 4);  // the bars case declares four references
    EXPECT_NEAR(std::stod(row[column(h, "error")]), largest, 1e-6 * largest);
    EXPECT_LT(std::stod(row[column(h, "momentum_error")]), 1e-12);
    EXPECT_GT(std::stol(row[column(h, "tets")]), 0);
  }
  // Finer mesh, smaller error (the bars' references at 10 and 20 cells along).
  EXPECT_LT(std::stod(rows[3][column(h, "error")]), std::stod(rows[1][column(h, "error")]));
}

TEST(Sweep, AgainstTheFinestRunItsOwnErrorIsZero) {
  const auto rows = sweep_bars("sweep-finest", "--reference finest");
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(std::stod(rows[2][column(rows[0], "error")]), 0.0);  // the finest
  EXPECT_GT(std::stod(rows[1][column(rows[0], "error")]), 0.0);
}

TEST(Sweep, BadInputIsRefusedBeforeAnythingRuns) {
  test::TempDir dir("sweep-bad");
  const std::string out = dir.str() + "/out";
  // A bad value in the second combination: nothing runs, nothing is written.
  auto r = test::run_cli("sweep " + k_bars + " --vary solver.cfl=0.5,-1 --quiet --out " + out,
                         dir.str());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("cfl"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
  // No reference to compare with.
  r = test::run_cli("sweep '" + test::source_path("data/cases/cubes-edge.yaml") +
                        "' --vary contact.passes=1,2 --quiet --out " + out,
                    dir.str());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--reference finest"), std::string::npos) << r.err;
  r = test::run_cli("sweep " + k_bars + " --quiet", dir.str());
  EXPECT_EQ(r.code, 2);
}
