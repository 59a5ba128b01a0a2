// `tetcontact campaign`: a case run per row of a table, predictions against measurements.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <sstream>
#include <tuple>

#include "../test_util.hpp"
#include "plate_case.hpp"
#include "tetcontact/app/runs.hpp"
#include "tetcontact/io/case.hpp"

using namespace tc;

namespace {

namespace fs = std::filesystem;

// A cube of side L in free flight: its length along x stays L exactly, whatever its material
// and speed; its mass is the material's density times L³. The table maps L (mm) and the metal.
const char* k_box = R"yaml(name: campaign-box
parameters:
  L: 1.0e-3
  v: 10
end_time: 1.0e-7
materials:
  m: {from: al6061-t6}
bodies:
  - name: box
    material: m
    mesh: {box: {size: ["= L", "= L", "= L"], cells: [1, 1, 1]}}
    velocity: [0, 0, "= -v"]
output: {interval: 1.0e-7, fields: [velocity]}
reference:
  - {name: box length, measure: length, body: box, axis: x}
campaign:
  parameters:
    L: {column: L_mm, factor: 1.0e-3}
    v: speed
  materials:
    m: {column: metal, names: {Al: al6061-t6, Cu: ofhc-copper}}
  compare:
    - {predicted: box length, measured: Lf_mm, factor: 1.0e-3, tolerance: 0.05}
  group_by: [metal]
)yaml";

// Row 3 is not measured; the errors of rows 1, 2 and 4 are 0, 2/2.5 − 1 and 1/0.8 − 1.
const char* k_boxes = R"csv(# boxes in free flight
metal,L_mm,speed,Lf_mm
Al,1.0,10,1.0
Cu,2.0,20,2.5
Al,1.5,5,
Cu,1.0,"10",0.8
)csv";

std::size_t run_folders(const std::string& dir) {
  std::size_t n = 0;
  for (const auto& e : fs::directory_iterator(dir + "/runs")) n += e.is_directory();
  return n;
}

}  // namespace

// A run killed within a campaign (its case writing checkpoints) goes on from its newest checkpoint
// when the campaign is run again: every run's summary the figures of the campaign never
// interrupted, the killed ones restarted.
TEST(Campaign, AKilledRunGoesOnFromItsCheckpoint) {
  test::TempDir dir("campaign-checkpoint");
  test::write_text(dir / "box.yaml", k_box);
  test::write_text(dir / "boxes.csv", k_boxes);
  const std::string cmd = "campaign '" + dir / "box.yaml" + "' '" + dir / "boxes.csv" +
                          "' --jobs 2 --set end_time=2.0e-5 --set output.checkpoint.steps=20 "
                          "--out '";
  const auto whole = test::run_cli(cmd + dir / "whole" + "'", dir.str());
  ASSERT_EQ(whole.code, 0) << whole.err;
  setenv("TETCONTACT_KILL_AT_STEP", "90", 1);  // every run killed at step 90 of 140 or more
  const auto killed = test::run_cli(cmd + dir / "out" + "'", dir.str());
  unsetenv("TETCONTACT_KILL_AT_STEP");
  EXPECT_NE(killed.code, 0);
  const auto resumed = test::run_cli(cmd + dir / "out" + "'", dir.str());
  ASSERT_EQ(resumed.code, 0) << resumed.err;
  const auto figures = [](test::Json s) {
    for (const char* k : {"wall_seconds", "timings", "restarts"}) s.erase(k);
    return s;
  };
  const auto rows = test::read_csv(dir / "out/predictions.csv");
  ASSERT_EQ(rows.size(), 4u);
  int restarted = 0;
  for (const auto& row : rows) {
    const std::string run = dir / "out/runs/" + row.at("folder");
    const test::Json s = test::read_json(run + "/summary.json");
    EXPECT_GT(test::number(s, "/steps"), 90) << row.at("folder");
    restarted += !s.at("restarts").empty();
    EXPECT_EQ(figures(s),
              figures(test::read_json(dir / "whole/runs/" + row.at("folder") + "/summary.json")))
        << row.at("folder");
  }
  EXPECT_EQ(restarted, 4);
}

// Rows become runs (a parameter from a column with its unit factor, a material slot from a name
// map), each prediction is compared with its row's measurement, and the statistics are the
// exact ones of those errors, overall and per group.
TEST(Campaign, RowsMapToParametersAndMaterialsAndTheErrorsAreExact) {
  test::TempDir dir("campaign");
  test::write_text(dir / "box.yaml", k_box);
  test::write_text(dir / "boxes.csv", k_boxes);
  const std::string out = dir / "out";
  const auto r = test::run_cli("campaign '" + dir / "box.yaml" + "' '" + dir / "boxes.csv" +
                                   "' --jobs 2 --out '" + out + "'",
                               dir.str());
  ASSERT_EQ(r.code, 0) << r.err;
  const auto rows = test::read_csv(out + "/predictions.csv");
  ASSERT_EQ(rows.size(), 4u);
  const double L[] = {1.0e-3, 2.0e-3, 1.5e-3, 1.0e-3}, rho[] = {2703, 8930, 2703, 8930};
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto& row = rows[i];
    EXPECT_EQ(row.at("row"), std::to_string(i + 1));
    EXPECT_EQ(row.at("status"), "ok");
    EXPECT_EQ(row.at("materials.m"), i % 2 ? "ofhc-copper" : "al6061-t6");
    EXPECT_NEAR(std::stod(row.at("predicted:box length")), L[i], 1e-12 * L[i]);
    // The run used the row's material and size: its mass is density × L³.
    const test::Json s = test::read_json(out + "/runs/" + row.at("folder") + "/summary.json");
    EXPECT_NEAR(s["bodies"][0]["mass"].get<double>(), rho[i] * L[i] * L[i] * L[i],
                1e-9 * rho[i] * L[i] * L[i] * L[i]);
  }
  EXPECT_EQ(rows[2].at("measured:box length"), "");  // not measured: predicted only
  EXPECT_EQ(rows[2].at("error:box length"), "");
  EXPECT_NEAR(std::stod(rows[1].at("error:box length")), 2.0 / 2.5 - 1.0, 1e-9);
  EXPECT_NEAR(std::stod(rows[3].at("error:box length")), 1.0 / 0.8 - 1.0, 1e-9);
  const test::Json stats = test::read_json(out + "/statistics.json");
  const test::Json& all = stats["comparisons"][0]["all"];
  EXPECT_EQ(all["compared"].get<int>(), 3);
  EXPECT_NEAR(all["median_abs_error"].get<double>(), 0.2, 1e-9);  // |e| = 0, 0.2, 0.25
  EXPECT_NEAR(all["p90_abs_error"].get<double>(), 0.25, 1e-9);    // nearest rank: the 3rd
  EXPECT_NEAR(all["mean_error"].get<double>(), (0.0 - 0.2 + 0.25) / 3.0, 1e-9);
  EXPECT_NEAR(all["within_tolerance"].get<double>(), 1.0 / 3.0, 1e-12);
  const test::Json& cu = stats["comparisons"][0]["groups"]["Cu"];
  EXPECT_EQ(cu["compared"].get<int>(), 2);
  EXPECT_NEAR(cu["median_abs_error"].get<double>(), 0.225, 1e-9);
  EXPECT_EQ(stats["comparisons"][0]["groups"]["Al"]["compared"].get<int>(), 1);
  EXPECT_NE(r.out.find("box length against Lf_mm"), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(out + "/campaign.png")) << r.err;

  // Run again: every row is read back, nothing runs, the predictions are the same.
  const std::string first = test::read_text(out + "/predictions.csv");
  const auto again = test::run_cli(
      "campaign '" + dir / "box.yaml" + "' '" + dir / "boxes.csv" + "' --out '" + out + "'",
      dir.str());
  ASSERT_EQ(again.code, 0) << again.err;
  EXPECT_NE(again.err.find("4 read from earlier runs, 0 to run"), std::string::npos) << again.err;
  EXPECT_EQ(test::read_text(out + "/predictions.csv"), first);
  // Another --set: its runs are new ones, beside the earlier (a run is keyed by every input).
  const auto other = test::run_cli("campaign '" + dir / "box.yaml" + "' '" + dir / "boxes.csv" +
                                       "' --out '" + out + "' --set end_time=2.0e-7",
                                   dir.str());
  ASSERT_EQ(other.code, 0) << other.err;
  EXPECT_NE(other.err.find("0 read from earlier runs, 4 to run"), std::string::npos) << other.err;
  EXPECT_EQ(run_folders(out), 8u);

  // --rows: conditions on a column and row ranges, all met.
  const auto some = test::run_cli("campaign '" + dir / "box.yaml" + "' '" + dir / "boxes.csv" +
                                      "' --out '" + out + "' --rows 'metal=Cu;1-3'",
                                  dir.str());
  ASSERT_EQ(some.code, 0) << some.err;
  const auto picked = test::read_csv(out + "/predictions.csv");
  ASSERT_EQ(picked.size(), 1u);
  EXPECT_EQ(picked[0].at("row"), "2");

  // A folder another campaign or search is running in is refused, naming its process, and
  // nothing in it changes; once that one has ended (its lock dropped), the folder is free.
  {
    const RunsFolderLock held = prepare_runs_folder(out);
    const auto busy = test::run_cli("campaign '" + dir / "box.yaml" + "' '" + dir / "boxes.csv" +
                                        "' --out '" + out + "' --set end_time=3.0e-7",
                                    dir.str());
    EXPECT_EQ(busy.code, 2) << busy.err;
    EXPECT_NE(busy.err.find("another search or campaign is running in this folder (process " +
                            std::to_string(getpid())),
              std::string::npos)
        << busy.err;
    EXPECT_EQ(run_folders(out), 8u);
    EXPECT_EQ(test::read_csv(out + "/predictions.csv").size(), 1u);
  }
  const auto after = test::run_cli("campaign '" + dir / "box.yaml" + "' '" + dir / "boxes.csv" +
                                       "' --out '" + out + "' --rows 1",
                                   dir.str());
  EXPECT_EQ(after.code, 0) << after.err;
}

// A case edited while its campaign runs: the runs still to start would read the new text under
// keys of the old one. The campaign stops (exit 2, naming the file) before any of them starts,
// sets aside a run that ended after the edit, writes no predictions, and every run it keeps ran
// the text of its key; started again it runs the rest with the new text.
TEST(Campaign, ACaseEditedWhileItsRunsGoOnStopsTheCampaign) {
  test::TempDir dir("campaign-edited");
  test::write_text(dir / "box.yaml", k_box);
  std::string table = "metal,L_mm,speed,Lf_mm\n";
  for (int i = 0; i < 40; ++i) table += "Al,1.0," + std::to_string(10 + i) + ",1.0\n";
  test::write_text(dir / "boxes.csv", table);
  const std::string out = dir / "out";
  // Start it, wait for its first finished run, then edit the case's end time.
  test::write_text(dir / "edit.sh",
                   "('" + std::string(TETCONTACT_BINARY) + "' campaign '" + dir / "box.yaml" +
                       "' '" + dir / "boxes.csv" + "' --jobs 1 --quiet --out '" + out + "' >'" +
                       dir / "out.txt" + "' 2>'" + dir / "err.txt" + "'; echo $? >'" +
                       dir / "code.txt" + "') &\n" +
                       "for i in $(seq 1 3000); do\n"
                       "  [ -n \"$(find '" +
                       out +
                       "' -name summary.json 2>/dev/null)\" ] && break; sleep 0.01\n"
                       "done\n"
                       "sed -i 's/^end_time: 1.0e-7$/end_time: 2.0e-7/' '" +
                       dir / "box.yaml" + "'\nwait\n");
  ASSERT_EQ(std::system(("bash '" + dir / "edit.sh" + "'").c_str()), 0);
  ASSERT_NE(test::read_text(dir / "box.yaml").find("end_time: 2.0e-7"), std::string::npos);
  EXPECT_EQ(test::read_text(dir / "code.txt"), "2\n");
  const std::string err = test::read_text(dir / "err.txt");
  EXPECT_NE(err.find(dir / "box.yaml" + ": changed while its runs went on"), std::string::npos)
      << err;
  EXPECT_FALSE(fs::exists(out + "/predictions.csv"));
  // The runs kept ran the old text; a run that ended after the edit (the first one too, when
  // the edit came before it was reaped) is set aside.
  std::size_t kept = 0, set_aside = 0;
  for (const auto& e : fs::directory_iterator(out + "/runs")) {
    set_aside += fs::exists(e.path() / "summary.json.stale");
    if (!fs::exists(e.path() / "summary.json")) continue;
    ++kept;
    EXPECT_EQ(test::read_json((e.path() / "summary.json").string())["end_time"].get<double>(),
              1.0e-7)
        << e.path();
  }
  EXPECT_GE(kept + set_aside, 1u);
  EXPECT_LT(kept + set_aside, 40u);
  EXPECT_NE(err.find(std::to_string(set_aside) + " run(s) that ended after the change set aside"),
            std::string::npos)
      << err;

  const auto again = test::run_cli("campaign '" + dir / "box.yaml" + "' '" + dir / "boxes.csv" +
                                       "' --jobs 2 --out '" + out + "'",
                                   dir.str());
  ASSERT_EQ(again.code, 0) << again.err;
  EXPECT_NE(again.err.find("0 read from earlier runs, 40 to run"), std::string::npos) << again.err;
  const auto rows = test::read_csv(out + "/predictions.csv");
  ASSERT_EQ(rows.size(), 40u);
  for (const auto& row : rows)
    EXPECT_EQ(test::read_json(out + "/runs/" + row.at("folder") + "/summary.json")["end_time"]
                  .get<double>(),
              2.0e-7);
}

// A campaign killed outright (SIGKILL: no handler runs) takes its runs with it, so that none
// goes on without the lock on its folder and races a campaign started again on it.
TEST(Campaign, ItsRunsEndWithIt) {
  test::TempDir dir("campaign-killed");
  test::write_text(dir / "box.yaml", k_box);
  test::write_text(dir / "boxes.csv", k_boxes);
  const std::string out = dir / "out";
  // Each run would take some 20 s (5 × 10^6 steps). Both start, the campaign is killed, and its
  // runs get about a second to end (those that end with it end at once); then whatever is left
  // is killed, so that the test leaves nothing behind.
  test::write_text(dir / "kill.sh",
                   "runs='" + out + "/runs/'\n'" + std::string(TETCONTACT_BINARY) + "' campaign '" +
                       dir / "box.yaml" + "' '" + dir / "boxes.csv" +
                       "' --rows 1-2 --jobs 2 --quiet --out '" + out +
                       "' --set end_time=0.5 --set output.interval=0.5 >/dev/null 2>&1 &\n"
                       R"sh(pid=$!
for i in $(seq 1 1000); do [ "$(pgrep -f -c "$runs")" -ge 2 ] && break; sleep 0.01; done
started=$(pgrep -f -c "$runs")
kill -9 $pid; wait $pid 2>/dev/null
for i in $(seq 1 50); do pgrep -f "$runs" >/dev/null || break; sleep 0.02; done
left=$(pgrep -f -c "$runs")
pkill -9 -f "$runs"
echo "$started $left" >')sh" +
                       dir / "counts.txt" + "'\n");
  ASSERT_EQ(std::system(("bash '" + dir / "kill.sh" + "'").c_str()), 0);
  EXPECT_EQ(test::read_text(dir / "counts.txt"), "2 0\n");  // two runs going, none after
}

// A table without the measured column still predicts (nothing compared); a bad table stops
// before any run with exit 2, naming the row and the column.
TEST(Campaign, BadTablesAreRefusedAndUnmeasuredTablesPredict) {
  test::TempDir dir("campaign-bad");
  test::write_text(dir / "box.yaml", k_box);
  test::write_text(dir / "plain.csv", "metal,L_mm,speed\nCu,1.0,10\n");
  const auto plain = test::run_cli("campaign '" + dir / "box.yaml" + "' '" + dir / "plain.csv" +
                                       "' --out '" + dir / "plain" + "'",
                                   dir.str());
  ASSERT_EQ(plain.code, 0) << plain.err;
  EXPECT_NE(plain.err.find("no column 'Lf_mm': box length is predicted, not compared"),
            std::string::npos)
      << plain.err;
  const auto rows = test::read_csv(dir / "plain/predictions.csv");
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_NEAR(std::stod(rows[0].at("predicted:box length")), 1.0e-3, 1e-15);
  EXPECT_EQ(test::read_json(dir / "plain/statistics.json")["comparisons"][0]["all"]["compared"]
                .get<int>(),
            0);

  struct Bad {
    std::string table, expect;
  };
  const std::vector<Bad> bad = {
      {"metal,L_mm,speed,Lf_mm\nAl,1,10,1\nAl,abc,10,1\n",
       "row 2 (line 3), column L_mm: 'abc' is not a number (it sets the parameter L)"},
      {"metal,L_mm,speed,Lf_mm\nAl,1,10,1\nFe,1,10,1\n",
       "row 2 (line 3), column metal: 'Fe' has no entry in campaign.materials.m.names"},
      {"metal,speed,Lf_mm\nAl,10,1\n", "no column 'L_mm', which the case's campaign reads"},
      {"metal,L_mm,speed,Lf_mm\nAl,1,10\n", "row 1 (line 2): 3 fields, the header has 4"},
      {"metal,L_mm,speed,Lf_mm\nAl,1,10,one\n",
       "row 1 (line 2), column Lf_mm: 'one' is not a number"},
      // A value the case refuses: the row, then the case's own message.
      {"metal,L_mm,speed,Lf_mm\nAl,-1,10,1\n", "row 1 (line 2): "},
  };
  for (const Bad& b : bad) {
    test::write_text(dir / "bad.csv", b.table);
    const auto r = test::run_cli(
        "campaign '" + dir / "box.yaml" + "' '" + dir / "bad.csv" + "' --out '" + dir / "bad" + "'",
        dir.str());
    EXPECT_EQ(r.code, 2) << b.table << r.err;
    EXPECT_NE(r.err.find(b.expect), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "bad")) << "nothing written for " << b.table;
  }
  // A case without a campaign block, and a row filter on a column the table lacks.
  const auto none = test::run_cli("campaign '" + test::source_path("data/cases/cubes-edge.yaml") +
                                      "' '" + dir / "plain.csv" + "' --out '" + dir / "bad" + "'",
                                  dir.str());
  EXPECT_EQ(none.code, 2);
  EXPECT_NE(none.err.find("no `campaign:` block"), std::string::npos) << none.err;
  const auto filter = test::run_cli("campaign '" + dir / "box.yaml" + "' '" + dir / "plain.csv" +
                                        "' --rows 'alloy=Cu' --out '" + dir / "bad" + "'",
                                    dir.str());
  EXPECT_EQ(filter.code, 2);
  EXPECT_NE(filter.err.find("no column 'alloy'"), std::string::npos) << filter.err;
  const auto op = test::run_cli("campaign '" + dir / "box.yaml" + "' '" + dir / "plain.csv" +
                                    "' --rows 'metal==Cu' --out '" + dir / "bad" + "'",
                                dir.str());
  EXPECT_EQ(op.code, 2);
  EXPECT_NE(op.err.find("the comparison is one of = != < <= > >="), std::string::npos) << op.err;
  EXPECT_FALSE(fs::exists(dir / "bad"));
}

// Categories: the perforation of a plate (the measure's 1 or 0 is the category P or NP) against
// a table's verdicts; the confusion table and the accuracy. The coarse 4 mm ball perforates the
// 1 mm plate at 1,400 m/s and not at 1,000 (Limit.BracketsThePerforationSpeed, its case); the
// third row's verdict is wrong on purpose.
TEST(Campaign, CategoriesGiveTheConfusionTable) {
  test::TempDir dir("campaign-categories");
  test::write_text(dir / "plate.yaml", std::string(test::k_plate) + R"yaml(
campaign:
  units_row: true
  parameters: {v: {column: velocity, factor: 1000}}
  compare:
    - {predicted: plate perforated, measured: result, categories: {P: 1, NP: 0}}
)yaml");
  test::write_text(dir / "shots.csv", "velocity,result\nkm/s,-\n1.0,NP\n1.4,P\n1.4,NP\n");
  const auto r = test::run_cli("campaign '" + dir / "plate.yaml" + "' '" + dir / "shots.csv" +
                                   "' --jobs 2 --out '" + dir / "out" + "'",
                               dir.str());
  ASSERT_EQ(r.code, 0) << r.err;
  const auto rows = test::read_csv(dir / "out/predictions.csv");
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0].at("predicted:plate perforated"), "NP");
  EXPECT_EQ(rows[1].at("predicted:plate perforated"), "P");
  EXPECT_EQ(rows[2].at("right:plate perforated"), "0");
  const test::Json all = test::read_json(dir / "out/statistics.json")["comparisons"][0]["all"];
  EXPECT_NEAR(all["accuracy"].get<double>(), 2.0 / 3.0, 1e-12);
  EXPECT_EQ(all["confusion"]["NP"]["NP"].get<int>(), 1);
  EXPECT_EQ(all["confusion"]["NP"]["P"].get<int>(), 1);
  EXPECT_EQ(all["confusion"]["P"]["P"].get<int>(), 1);
  EXPECT_EQ(all["confusion"]["P"]["NP"].get<int>(), 0);
  // Christiansen's equation beside the engine, on each row's shot: its critical diameter, its
  // verdict and whether it is right; its accuracy over the rows.
  int equation_right = 0;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const tc::Case c =
        tc::load_case(dir / "plate.yaml", {"parameters.v=" + rows[i].at("parameters.v")});
    const tc::ShieldEquationVerdict e = tc::christiansen_verdict(c.shield_equation.shot);
    EXPECT_NEAR(std::stod(rows[i].at("equation:critical_diameter")), e.critical_diameter,
                1e-6 * e.critical_diameter);
    EXPECT_EQ(rows[i].at("equation:plate perforated"), e.perforated ? "P" : "NP");
    const bool right = (e.perforated ? "P" : "NP") == rows[i].at("measured:plate perforated");
    EXPECT_EQ(rows[i].at("right:equation"), right ? "1" : "0");
    equation_right += right;
    // The run's summary: both verdicts, and a note exactly when they disagree.
    const test::Json s = test::read_json(
        dir / ("out/runs/" + rows[i].at("folder") + "/summary.json"))["shield_equation"];
    const bool engine = rows[i].at("predicted:plate perforated") == "P";
    EXPECT_EQ(s["engine_perforated"].get<bool>(), engine);
    EXPECT_EQ(s["perforated"].get<bool>(), e.perforated);
    EXPECT_EQ(s["agree"].get<bool>(), engine == e.perforated);
    EXPECT_EQ(s["note"].is_string(), engine != e.perforated) << s.dump();
  }
  EXPECT_NEAR(all["equation_accuracy"].get<double>(), equation_right / 3.0, 1e-12);
  // A verdict that is no category: the row and the column.
  test::write_text(dir / "odd.csv", "velocity,result\nkm/s,-\n1.0,maybe\n");
  const auto odd = test::run_cli(
      "campaign '" + dir / "plate.yaml" + "' '" + dir / "odd.csv" + "' --out '" + dir / "odd" + "'",
      dir.str());
  EXPECT_EQ(odd.code, 2);
  EXPECT_NE(odd.err.find("row 1 (line 3), column result: 'maybe' is none of the categories P, NP"),
            std::string::npos)
      << odd.err;
}

// The shipped templates read every row of the shared tables: each names a library material
// through the case's map (every alloy of the Whipple database, every rod metal) and makes a
// valid case (`--check` runs nothing).
TEST(Campaign, EveryRowOfTheSharedTablesMakesAValidCase) {
  test::TempDir dir("campaign-check");
  for (const auto& [c, table, rows] :
       std::vector<std::tuple<std::string, std::string, std::string>>{
           {"data/cases/taylor.yaml", "data/validation/taylor-tests.csv", "156 of 156 rows"},
           {"data/cases/whipple.yaml", "data/validation/whipple-shots.csv", "932 of 932 rows"}}) {
    const auto r =
        test::run_cli("campaign '" + test::source_path(c) + "' '" + test::source_path(table) +
                          "' --check --out '" + dir / "never" + "'",
                      dir.str());
    EXPECT_EQ(r.code, 0) << c << "\n" << r.err;
    EXPECT_NE(r.out.find(rows + " of "), std::string::npos) << r.out;
    EXPECT_FALSE(fs::exists(dir / "never"));
  }
}
