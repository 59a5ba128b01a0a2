// Processes change who computes, never what: `mpirun -np N tetcontact run CASE`
// writes the same frames, particle frames, history and summary figures as one process, bit
// for bit, for N = 1 to 4 (oversubscribed on a 2-core machine). A failure on any rank stops
// every rank with the one process's message and exit code; bad input stops them all at once.
// ctest -L mpi.
#include <gtest/gtest.h>

#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "../test_util.hpp"

using namespace tc;

namespace {

namespace fs = std::filesystem;

std::string quote(const std::string& s) {
  return "'" + s + "'";
}

// `tetcontact ARGS` under mpirun with n processes (0: without mpirun).
test::CliResult launch(int n, const std::string& args, const std::string& scratch) {
  if (n == 0) return test::run_cli(args, scratch);
  const std::string out = scratch + "/.stdout", err = scratch + "/.stderr";
  const std::string cmd = "mpirun --allow-run-as-root --oversubscribe -np " + std::to_string(n) +
                          " '" + TETCONTACT_BINARY + "' " + args + " >'" + out + "' 2>'" + err +
                          "' </dev/null";
  const int status = std::system(cmd.c_str());
  test::CliResult r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = test::read_text(out);
  r.err = test::read_text(err);
  return r;
}

// The summary less what measures the machine rather than the run.
test::Json figures(test::Json s) {
  for (const char* k : {"wall_seconds", "timings", "threads", "parallel", "modules"}) s.erase(k);
  return s;
}

// tools/post/check_vtu.py ARGS (VTK's own readers): its exit code.
int check_vtu(const std::string& args) {
  const std::string cmd = "/usr/bin/python3 '" + test::source_path("tools/post/check_vtu.py") +
                          "' " + args + " >/dev/null";
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// Runs a case as one process, then on each of `ranks` processes: the frames (per-rank pieces
// joined by a .pvtu) must hold the one process's values bit for bit, node by node and cell by
// cell, as VTK reads them; every other file (particle frames and their series) the same bytes,
// the history the same but for its wall-clock columns, the summary the same figures. Returns
// the one process's summary.
test::Json same_on_any_rank_count(const std::string& name, const std::string& case_file,
                                  const std::string& sets, const std::vector<int>& ranks) {
  test::TempDir dir("mpi-" + name);
  const std::string args = "run " + quote(test::source_path(case_file)) + " --quiet " + sets;
  const auto one = launch(0, args + " --out " + quote(dir / "serial"), dir.str());
  EXPECT_EQ(one.code, 0) << one.err;
  const fs::path serial = dir / "serial";
  const test::Json summary = test::read_json((serial / "summary.json").string());
  EXPECT_EQ(test::number(summary, "/parallel/ranks"), 1);
  for (const int n : ranks) {
    const fs::path out = dir / std::to_string(n);
    const auto r = launch(n, args + " --out " + quote(out.string()), dir.str());
    EXPECT_EQ(r.code, 0) << name << " on " << n << " ranks: " << r.err;
    // Every file but the frames (pieces on several ranks) and the three compared below is the
    // same byte for byte (the particles' series); both runs wrote the same such files.
    const auto others = [](const fs::path& dir) {
      std::set<std::string> names;
      for (const auto& e : fs::recursive_directory_iterator(dir)) {
        const std::string file = fs::relative(e.path(), dir).string();
        if (e.is_regular_file() && file != "summary.json" && file != "history.csv" &&
            file != "case.pvd" && file.rfind("frame_", 0) != 0)
          names.insert(file);
      }
      return names;
    };
    const std::set<std::string> files = others(serial);
    EXPECT_EQ(files, others(out)) << name << " on " << n << " ranks";
    for (const std::string& rel : files)
      EXPECT_TRUE(test::read_text((serial / rel).string()) == test::read_text((out / rel).string()))
          << name << ": " << rel << " differs on " << n << " ranks";
    // A run with particles compares their series: never nothing.
    const test::Json& particles = summary.at("fracture").at("particles");
    if (particles.is_number() && particles.get<long>() > 0) {
      EXPECT_TRUE(files.count("particles.pvd") && files.count("particles_0000.vtu")) << name;
    }
    EXPECT_EQ(check_vtu("--same '" + serial.string() + "' '" + out.string() + "'"), 0)
        << name << " on " << n << " ranks: the frames differ (check_vtu.py --same)";
    EXPECT_EQ(test::history_without_timings(serial / "history.csv"),
              test::history_without_timings(out / "history.csv"))
        << name << " on " << n << " ranks";
    const test::Json other = test::read_json((out / "summary.json").string());
    EXPECT_EQ(figures(summary), figures(other)) << name << " on " << n << " ranks";
    // The decomposition it ran on: every tet on one rank.
    EXPECT_EQ(test::number(other, "/parallel/ranks"), n);
    if (n > 1) {
      long tets = 0;
      for (const auto& piece : other.at("parallel").at("partition").at("pieces"))
        tets += piece.at("tets").get<long>();
      EXPECT_EQ(tets, static_cast<long>(test::number(summary, "/mesh/tets"))) << name;
    }
  }
  return summary;
}

}  // namespace

TEST(Mpi, CubesWithEdgeContactAreBitIdenticalOn1To4Ranks) {
  const test::Json s =
      same_on_any_rank_count("cubes", "data/cases/cubes-edge.yaml", "", {1, 2, 3, 4});
  EXPECT_GT(test::number(s, "/contact/edge_edge"), 0);
}

// The pieces and the .pvtu that joins them open in VTK's reader (the one ParaView uses) and
// pass check_vtu.py's checks (every node in a piece, every cell once, arrays and volumes).
TEST(Mpi, PiecesAndPvtuOpenInVtksReader) {
  test::TempDir dir("mpi-pvtu");
  const std::string out = dir / "o";
  const auto r = launch(3,
                        "run " + quote(test::source_path("data/cases/spall-plate.yaml")) +
                            " --quiet --set end_time=2.0e-6 --set output.interval=1.0e-6 --set "
                            "'output.fields=[displacement,velocity,stress,pressure,body,von_mises]'"
                            " --out " +
                            quote(out),
                        dir.str());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(out + "/frame_0001.pvtu"));
  for (const char* piece : {"frame_0001_r0.vtu", "frame_0001_r1.vtu", "frame_0001_r2.vtu"})
    EXPECT_TRUE(fs::exists(out + "/" + piece)) << piece;
  EXPECT_FALSE(fs::exists(out + "/frame_0001.vtu"));
  // The case's gauge: the rows of one process, bit for bit (its cell's owner sends its fields).
  const auto one = launch(0,
                          "run " + quote(test::source_path("data/cases/spall-plate.yaml")) +
                              " --quiet --set end_time=2.0e-6 --set output.interval=1.0e-6 --out " +
                              quote(dir / "one"),
                          dir.str());
  ASSERT_EQ(one.code, 0) << one.err;
  EXPECT_GT(test::read_text(dir / "one/gauges.csv").size(), 1000u);
  EXPECT_EQ(test::read_text(out + "/gauges.csv"), test::read_text(dir / "one/gauges.csv"));
  EXPECT_EQ(check_vtu("'" + out + "'"), 0);
  // The checks can fail: a piece missing.
  fs::remove(out + "/frame_0001_r1.vtu");
  EXPECT_NE(check_vtu("'" + out + "'"), 0);
  // The partition the run used, in its summary: every tet on one rank, imbalance measured.
  const test::Json s = test::read_json(out + "/summary.json");
  long tets = 0;
  for (const auto& piece : s.at("parallel").at("partition").at("pieces"))
    tets += piece.at("tets").get<long>();
  EXPECT_EQ(tets, static_cast<long>(test::number(s, "/mesh/tets")));
  EXPECT_GE(test::number(s, "/parallel/partition/tet_imbalance"), 1.0);
  EXPECT_EQ(s.at("parallel").at("partition").at("pieces").size(), 3u);
  for (const auto& piece : s.at("parallel").at("partition").at("pieces"))
    EXPECT_TRUE(piece.contains("shared_nodes") && piece.contains("ghost_nodes"));
}

TEST(Mpi, CoarseCylindersWithEdgeEdgeAndVerificationAreBitIdenticalOn2To4Ranks) {
  const test::Json s = same_on_any_rank_count(
      "cylinders", "data/cases/cylinders.yaml",
      "--set contact.edge_edge=true --set contact.verify=true --set end_time=3.0e-6 "
      "--set bodies.0.mesh.cylinder.cells_across=8 --set bodies.0.mesh.cylinder.cells_axial=8 "
      "--set bodies.1.mesh.cylinder.cells_across=4 --set bodies.1.mesh.cylinder.cells_axial=4",
      {2, 3, 4});
  EXPECT_GT(test::number(s, "/contact/edge_edge"), 0);
  EXPECT_GT(test::number(s, "/contact/verification/pairs_checked"), 0);
  // Ranks and threads together: 2 ranks of 2 threads against one process of 2 threads.
  same_on_any_rank_count("cylinders-threads", "data/cases/cylinders.yaml",
                         "--threads 2 --set contact.edge_edge=true --set contact.verify=true "
                         "--set end_time=1.0e-6 --set bodies.0.mesh.cylinder.cells_across=8 "
                         "--set bodies.0.mesh.cylinder.cells_axial=8 "
                         "--set bodies.1.mesh.cylinder.cells_across=4 "
                         "--set bodies.1.mesh.cylinder.cells_axial=4",
                         {2});
}

TEST(Mpi, CoarseBallPlateWithFractureAndParticlesIsBitIdenticalOn2To4Ranks) {
  const test::Json s = same_on_any_rank_count(
      "ball-plate", "data/cases/ball-plate.yaml",
      "--set bodies.0.mesh.sphere.cells_across=8 --set 'bodies.1.mesh.box.cells=[24,24,2]' "
      "--set end_time=1.5e-6",
      {2, 3, 4});
  EXPECT_GT(test::number(s, "/fracture/particles"), 50);
  EXPECT_GT(test::number(s, "/contact/node_face"), 0);
}

// With contact heat: the heat of the exchanges is the same on every rank, so every cell's and
// particle's energy is too.
TEST(Mpi, CoarseBallPlateWithContactHeatIsBitIdenticalOn2And3Ranks) {
  const test::Json s = same_on_any_rank_count(
      "ball-plate-heat", "data/cases/ball-plate.yaml",
      "--set bodies.0.mesh.sphere.cells_across=8 --set 'bodies.1.mesh.box.cells=[24,24,2]' "
      "--set end_time=1.5e-6 --set contact.heat=true",
      {2, 3});
  EXPECT_GT(test::number(s, "/fracture/particles"), 50);
  EXPECT_GT(test::number(s, "/energy/contact_heat"),
            0.5 * -test::number(s, "/energy/contact_work"));
}

// With fragments as clusters: the joins, made on every rank from the same gathered state, give
// every rank the same particles.
TEST(Mpi, CoarseBallPlateWithClustersIsBitIdenticalOn2And3Ranks) {
  const test::Json s = same_on_any_rank_count(
      "ball-plate-clusters", "data/cases/ball-plate.yaml",
      "--set bodies.0.mesh.sphere.cells_across=8 --set 'bodies.1.mesh.box.cells=[24,24,2]' "
      "--set end_time=1.5e-6 --set fracture.fragments=clusters",
      {2, 3});
  EXPECT_GT(test::number(s, "/fracture/cells_joined_to_clusters"), 50);  // 119 of 282
}

// Johnson–Cook ductile failure on the coarse Whipple shield: the damage, its part at the failure
// strain's floor and the cells it erodes are the one process's on every rank.
TEST(Mpi, CoarseWhippleShieldWithDuctileFailureIsBitIdenticalOn2And3Ranks) {
  const test::Json s = same_on_any_rank_count(
      "whipple-ductile", "data/cases/whipple.yaml",
      "--set parameters.hb=1.0e-3 --set parameters.hw=2.0e-3 --set parameters.np=6 "
      "--set parameters.tear=5.0e-6 --set parameters.S=15e-3 --set parameters.ww=30e-3",
      {2, 3});
  EXPECT_GT(test::number(s, "/fracture/ductile_failed_at_floor"), 100);  // 277 of 281
}

// The coarse Whipple quarter verified, edge–edge contact on: steps whose failures the further
// passes leave are taken again shorter, and a zone acts; every rank takes the same decisions
// (the verification is whole on each), so the run is the one process's.
TEST(Mpi, CoarseVerifiedWhippleShieldWithShorterStepsIsBitIdenticalOn2And3Ranks) {
  const test::Json s = same_on_any_rank_count(
      "whipple-verified", "data/cases/whipple.yaml",
      "--set parameters.hb=1.0e-3 --set parameters.hw=2.0e-3 --set parameters.np=6 "
      "--set parameters.tear=5.0e-6 --set parameters.S=15e-3 --set parameters.cb=24e-3 "
      "--set parameters.ww=30e-3 --set parameters.cw=30e-3 --set contact.edge_edge=true "
      "--set contact.verify=true",
      {2, 3});
  EXPECT_GT(test::number(s, "/contact/verification/step_cuts"), 5);  // 13 measured
  EXPECT_EQ(test::number(s, "/contact/verification/unresolved_steps"), 0);
}

// SPH debris on the coarse Whipple shield: every rank runs the particles whole, as one process.
TEST(Mpi, CoarseWhippleShieldWithSphDebrisIsBitIdenticalOn2And3Ranks) {
  const test::Json s = same_on_any_rank_count(
      "whipple-sph", "data/cases/whipple.yaml",
      "--set parameters.hb=1.0e-3 --set parameters.hw=2.0e-3 --set parameters.np=6 "
      "--set parameters.tear=2.0e-6 --set parameters.S=15e-3 --set parameters.ww=30e-3 "
      "--set fracture.debris=sph",
      {2, 3});
  EXPECT_GT(test::number(s, "/fracture/particles"), 100);
  EXPECT_GT(test::number(s, "/fracture/sph/neighbours_per_particle"), 5);
}

TEST(Mpi, BarsAndATaylorRodWithNodalPressureAreBitIdenticalOn2To4Ranks) {
  const test::Json bars = same_on_any_rank_count("bars", "data/cases/bars-impact.yaml",
                                                 "--set end_time=20.0e-6", {2, 3, 4});
  EXPECT_GT(test::number(bars, "/contact/node_face"), 0);
  const test::Json taylor =
      same_on_any_rank_count("taylor", "data/cases/taylor-copper.yaml",
                             "--set end_time=3.0e-6 --set bodies.0.mesh.cylinder.cells_across=6 "
                             "--set bodies.0.mesh.cylinder.cells_axial=30",
                             {2, 3, 4});
  EXPECT_GT(test::number(taylor, "/walls/0/max_force"), 0);
}

TEST(Mpi, AStabilityCaseIsBitIdenticalOn2To4Ranks) {
  const test::Json s =
      same_on_any_rank_count("hypervelocity", "data/cases/stability/hypervelocity.yaml",
                             "--set end_time=0.6e-6", {2, 3, 4});
  EXPECT_GT(test::number(s, "/steps"), 10);
}

// An element that inverts on one rank stops every rank: exit 1, the one process's message
// (naming the body and its tet), and the summary says so.
TEST(Mpi, AnInvertedElementStopsEveryRankWithTheOneProcessMessage) {
  test::TempDir dir("mpi-inverted");
  std::string yaml = test::read_text(test::source_path("data/cases/micro/coincident-faces.yaml"));
  const std::string slow = "velocity: [7, 3, -100]";
  ASSERT_NE(yaml.find(slow), std::string::npos);
  yaml.replace(yaml.find(slow), slow.size(), "velocity: [0, 0, -2.0e5]");  // crushes the tets
  test::write_text(dir / "crash.yaml", yaml);
  std::string status;
  for (const int n : {0, 3}) {
    const std::string out = dir / ("out" + std::to_string(n));
    // Without the verification, whose impact zones would carry the crushed faces rigidly.
    const auto r = launch(n,
                          "run " + quote(dir / "crash.yaml") +
                              " --quiet --set contact.verify=false --out " + quote(out),
                          dir.str());
    EXPECT_EQ(r.code, 1) << n << " ranks: " << r.err;
    const test::Json s = test::read_json(out + "/summary.json");
    const std::string st = s.at("status").get<std::string>();
    EXPECT_NE(st.find("inverted"), std::string::npos) << st;
    EXPECT_NE(st.find(", tet "), std::string::npos) << st;
    if (n == 0) status = st;
    EXPECT_EQ(st, status);
    // Said once, by rank 0.
    const std::size_t first = r.err.find("run failed");
    EXPECT_NE(first, std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("run failed", first + 1), std::string::npos) << r.err;
  }
}

// Bad input and a folder that exists: every rank stops with exit 2 before writing anything,
// and the message comes once. Commands other than `run` refuse to run on several processes.
TEST(Mpi, BadInputStopsEveryRankAndOtherCommandsRefuseSeveralProcesses) {
  test::TempDir dir("mpi-bad-input");
  const std::string cubes = quote(test::source_path("data/cases/cubes-edge.yaml"));
  auto r = launch(3, "run " + quote(dir / "none.yaml") + " --out " + quote(dir / "o"), dir.str());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("none.yaml"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("none.yaml"), r.err.rfind("none.yaml")) << r.err;
  EXPECT_FALSE(fs::exists(dir / "o"));
  r = launch(2, "run " + cubes + " --quiet --out " + quote(dir / "o"), dir.str());
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string before = test::read_text(dir / "o/summary.json");
  r = launch(2, "run " + cubes + " --quiet --out " + quote(dir / "o"), dir.str());  // no --force
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_EQ(test::read_text(dir / "o/summary.json"), before);
  // --force clears a distributed run's files too: no piece of a 3-rank run stays beside a
  // 2-rank one.
  r = launch(3, "run " + cubes + " --quiet --force --out " + quote(dir / "o"), dir.str());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir / "o/frame_0000_r2.vtu"));
  r = launch(2, "run " + cubes + " --quiet --force --out " + quote(dir / "o"), dir.str());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_FALSE(fs::exists(dir / "o/frame_0000_r2.vtu"));
  EXPECT_TRUE(fs::exists(dir / "o/frame_0000_r1.vtu"));
  // More ranks than tets: refused before anything is written, said once.
  r = launch(7,
             "run " + quote(test::source_path("data/cases/elastic-vibration.yaml")) +
                 " --quiet --set 'bodies.0.mesh.box.cells=[1,1,1]' --out " + quote(dir / "few"),
             dir.str());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("cannot run on 7 processes"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("cannot run on"), r.err.rfind("cannot run on")) << r.err;
  EXPECT_FALSE(fs::exists(dir / "few"));
  r = launch(2, "check " + cubes, dir.str());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("only `run` runs distributed"), std::string::npos) << r.err;
}

// A distributed run killed (one rank by SIGKILL, mpirun ending the others) goes on from its
// newest checkpoint on 2 ranks: the frames, history and summary of the 2-rank run never
// interrupted, bit for bit (the checkpoint holds every tet's fields, gathered from the ranks).
TEST(Mpi, AKilledDistributedRunGoesOnFromItsCheckpointBitForBit) {
  test::TempDir dir("mpi-restart");
  const std::string args = "run " + quote(test::source_path("data/cases/cylinders.yaml")) +
                           " --quiet --threads 1 --set output.checkpoint.steps=100";
  const std::string whole = dir / "whole", cut = dir / "cut";
  auto r = launch(2, args + " --out " + quote(whole), dir.str());
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string killed =
      "TETCONTACT_KILL_AT_STEP=250 mpirun --allow-run-as-root "
      "--oversubscribe -x TETCONTACT_KILL_AT_STEP -np 2 '" +
      std::string(TETCONTACT_BINARY) + "' " + args + " --out " + quote(cut) +
      " >/dev/null 2>&1 </dev/null";
  const int status = std::system(killed.c_str());
  EXPECT_NE(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 0);
  ASSERT_TRUE(fs::exists(cut + "/checkpoints/step_0000000200.ckpt"));
  EXPECT_FALSE(fs::exists(cut + "/summary.json"));
  r = launch(2, args + " --restart " + quote(cut), dir.str());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("restarting from"), std::string::npos) << r.err;
  // Every file the same bytes (the pieces, the .pvtu, the series), the history but for its
  // wall-clock columns, the summary's figures.
  std::set<std::string> files;
  for (const auto& e : fs::directory_iterator(whole)) files.insert(e.path().filename().string());
  std::set<std::string> cut_files;
  for (const auto& e : fs::directory_iterator(cut)) cut_files.insert(e.path().filename().string());
  EXPECT_EQ(files, cut_files);
  EXPECT_TRUE(files.count("frame_0006_r1.vtu") && files.count("frame_0006.pvtu"));
  for (const std::string& f : files) {
    if (f == "summary.json" || f == "history.csv") continue;
    EXPECT_TRUE(test::read_text(whole + "/" + f) == test::read_text(cut + "/" + f)) << f;
  }
  EXPECT_EQ(test::history_without_timings(fs::path(whole) / "history.csv"),
            test::history_without_timings(fs::path(cut) / "history.csv"));
  test::Json restarted = test::read_json(cut + "/summary.json");
  EXPECT_EQ(restarted.at("restarts").at(0).at("step"), 200);
  restarted.erase("restarts");
  test::Json uninterrupted = test::read_json(whole + "/summary.json");
  EXPECT_EQ(uninterrupted.at("restarts").size(), 0u);
  uninterrupted.erase("restarts");
  EXPECT_EQ(figures(uninterrupted), figures(restarted));
}
