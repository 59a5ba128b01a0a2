// Checkpoint and restart: a run killed by a signal goes on from its newest checkpoint and ends with
// the frames, history and summary of the run never interrupted, bit for bit; checkpoints of
// another case, another build or damaged ones are refused before anything is written.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <set>
#include <sstream>

#include "../test_util.hpp"

using namespace tc;
namespace fs = std::filesystem;

namespace {

std::string quote(const std::string& s) {
  return "'" + s + "'";
}

// `tetcontact ARGS` killed (SIGKILL, as an out-of-memory killer would) right after step `step`.
test::CliResult run_killed_at(long step, const std::string& args, const std::string& scratch) {
  setenv("TETCONTACT_KILL_AT_STEP", std::to_string(step).c_str(), 1);
  const test::CliResult r = test::run_cli(args, scratch);
  unsetenv("TETCONTACT_KILL_AT_STEP");
  return r;
}

// The summary less what measures the machine rather than the run (the threads may differ).
test::Json figures(test::Json s) {
  for (const char* k : {"wall_seconds", "timings", "threads", "parallel", "restarts"}) s.erase(k);
  return s;
}

std::set<std::string> files_in(const fs::path& dir) {
  std::set<std::string> names;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) names.insert(fs::relative(e.path(), dir).string());
  return names;
}

// Two run folders hold the same run: the same files, every one the same bytes but the history
// (the same but for its wall-clock columns) and the summary (the same figures).
void expect_same_run(const fs::path& a, const fs::path& b) {
  const std::set<std::string> files = files_in(a);
  EXPECT_EQ(files, files_in(b));
  for (const std::string& f : files) {
    if (f == "summary.json" || f == "history.csv") continue;
    EXPECT_TRUE(test::read_text((a / f).string()) == test::read_text((b / f).string()))
        << f << " differs";
  }
  EXPECT_EQ(test::history_without_timings(a / "history.csv"),
            test::history_without_timings(b / "history.csv"));
  EXPECT_EQ(figures(test::read_json((a / "summary.json").string())),
            figures(test::read_json((b / "summary.json").string())));
}

// A case run whole, then killed after `kill_step` and restarted with --restart (checkpoints every
// `every` steps; `threads_whole`, `threads_cut`, `threads_restart` threads): the two folders hold
// the same run. Returns the whole run's summary.
test::Json killed_and_restarted(const std::string& name, const std::string& case_args, long every,
                                long kill_step, int threads_whole, int threads_cut,
                                int threads_restart) {
  test::TempDir dir("checkpoint-" + name);
  const std::string args =
      "run " + case_args + " --quiet --set output.checkpoint.steps=" + std::to_string(every);
  const auto threads = [](int n) { return " --threads " + std::to_string(n); };
  const std::string whole = dir / "whole", cut = dir / "cut";
  const auto w = test::run_cli(args + threads(threads_whole) + " --out " + quote(whole), dir.str());
  EXPECT_EQ(w.code, 0) << w.err;
  // Its checkpoints are gone with its end (a run that has ended is not restarted).
  EXPECT_FALSE(fs::exists(whole + "/checkpoints"));
  const auto k =
      run_killed_at(kill_step, args + threads(threads_cut) + " --out " + quote(cut), dir.str());
  EXPECT_EQ(k.code, 128 + 9) << "killed by SIGKILL: " << k.err;
  EXPECT_FALSE(fs::exists(cut + "/summary.json"));
  EXPECT_FALSE(fs::exists(cut + "/history.csv")) << "the history is moved into place at the end";
  // The newest two checkpoints are kept; the restart goes on from the newest.
  const long last = kill_step / every * every;
  char newest[40], older[40];
  std::snprintf(newest, sizeof newest, "step_%010ld.ckpt", last);
  std::snprintf(older, sizeof older, "step_%010ld.ckpt", last - every);
  EXPECT_EQ(files_in(cut + "/checkpoints"),
            (std::set<std::string>{std::string(older), std::string(newest)}));
  const auto r =
      test::run_cli(args + threads(threads_restart) + " --restart " + quote(cut), dir.str());
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("restarting from " + cut + "/checkpoints/" + newest), std::string::npos)
      << r.err;
  expect_same_run(whole, cut);
  // The summary says where the run went on from; the uninterrupted run's says none.
  const test::Json restarts = test::read_json(cut + "/summary.json").at("restarts");
  EXPECT_EQ(restarts.size(), 1u);
  EXPECT_EQ(restarts.at(0).at("step").get<long>(), last);
  EXPECT_TRUE(test::read_json(whole + "/summary.json").at("restarts").empty());
  return test::read_json(whole + "/summary.json");
}

const std::string k_spall = test::source_path("data/cases/spall-plate.yaml");

}  // namespace

// The paper's cylinders with edge–edge contact and the verified step (binding lists, the
// verifier's lists, the edge pairs in contact carried over), killed at step 250 of 714 and
// restarted from step 200 on another thread count.
TEST(Checkpoint, TheCylindersKilledGoOnBitForBit) {
  const test::Json s = killed_and_restarted(
      "cylinders", quote(test::source_path("data/cases/cylinders.yaml")), 100, 250, 2, 1, 2);
  EXPECT_GT(test::number(s, "/contact/edge_edge"), 0);
}

// A coarse Whipple shot with SPH debris (cells converted, the SPH particles' last forces and lists,
// the symmetry planes' images, erosion), killed at step 1,500 of about 2,700 and restarted from
// step 1,200 on one thread.
TEST(Checkpoint, ACoarseWhippleShotWithSphDebrisKilledGoesOnBitForBit) {
  const test::Json s = killed_and_restarted(
      "whipple",
      quote(test::source_path("data/cases/whipple.yaml")) +
          " --set parameters.hb=1.0e-3 --set parameters.hw=2.0e-3 --set parameters.np=6"
          " --set parameters.tear=2.0e-6 --set parameters.S=15e-3 --set "
          "parameters.ww=30e-3 --set fracture.debris=sph",
      400, 1500, 2, 2, 1);
  EXPECT_GT(test::number(s, "/fracture/particles"), 100);
}

// The spall plate: its gauges' rows, its particles' series and its references carry over.
TEST(Checkpoint, TheSpallPlateKilledGoesOnWithItsGauges) {
  const test::Json s = killed_and_restarted("spall", quote(k_spall), 150, 500, 1, 1, 1);
  EXPECT_GT(test::number(s, "/fracture/particles"), 0);
}

// SIGTERM (a batch queue's notice) or SIGINT in a run with checkpoints: the step under way ends,
// its checkpoint is written and the run stops (exit 128 + the signal), losing nothing; the
// restart ends as the run never interrupted.
TEST(Checkpoint, ASigtermStopsTheRunWithACheckpointOfItsLastStep) {
  test::TempDir dir("checkpoint-sigterm");
  const std::string args = "run " + quote(k_spall) + " --quiet";
  const auto w = test::run_cli(args + " --out " + quote(dir / "whole"), dir.str());
  ASSERT_EQ(w.code, 0) << w.err;
  // Checkpoints every 100,000 steps: none due in the run; the signal's is the only one.
  const std::string sets = " --set output.checkpoint.steps=100000";
  setenv("TETCONTACT_KILL_SIGNAL", "15", 1);
  const auto k = run_killed_at(333, args + sets + " --out " + quote(dir / "cut"), dir.str());
  unsetenv("TETCONTACT_KILL_SIGNAL");
  EXPECT_EQ(k.code, 128 + 15) << k.err;
  EXPECT_NE(k.err.find("stopped by signal 15 after step 333"), std::string::npos) << k.err;
  EXPECT_EQ(files_in(dir / "cut/checkpoints"), std::set<std::string>{"step_0000000333.ckpt"});
  EXPECT_FALSE(fs::exists(dir / "cut/summary.json"));
  const auto r = test::run_cli(args + sets + " --restart " + quote(dir / "cut"), dir.str());
  ASSERT_EQ(r.code, 0) << r.err;
  expect_same_run(dir / "whole", dir / "cut");
  // Without checkpoints a signal ends the run as it always did: nothing is written for it.
  setenv("TETCONTACT_KILL_SIGNAL", "15", 1);
  const auto plain = run_killed_at(333, args + " --out " + quote(dir / "plain"), dir.str());
  unsetenv("TETCONTACT_KILL_SIGNAL");
  EXPECT_EQ(plain.code, 128 + 15);
  EXPECT_FALSE(fs::exists(dir / "plain/checkpoints"));
}

// What cannot be gone on from is refused (exit 2, the file named, nothing written), and a
// restart that can, can only once.
TEST(Checkpoint, AnotherCasesBuildsOrADamagedCheckpointIsRefused) {
  test::TempDir dir("checkpoint-refused");
  const std::string cut = dir / "cut";
  const std::string args = "run " + quote(k_spall) + " --quiet --set output.checkpoint.steps=100";
  ASSERT_EQ(run_killed_at(250, args + " --out " + quote(cut), dir.str()).code, 137);
  const std::string ckpt = cut + "/checkpoints/step_0000000200.ckpt";
  ASSERT_TRUE(fs::exists(ckpt));
  const std::set<std::string> before = files_in(cut);
  const std::string good = test::read_text(ckpt);
  const auto refused = [&](const std::string& extra, const std::string& why) {
    const auto r = test::run_cli(args + " --restart " + quote(cut) + extra, dir.str());
    EXPECT_EQ(r.code, 2) << extra << ": " << r.err;
    EXPECT_NE(r.err.find(why), std::string::npos) << r.err;
    EXPECT_EQ(files_in(cut), before) << "nothing written: " << extra;
  };
  // Other inputs: an override the run was not started with.
  refused(" --set end_time=3.0e-6", ckpt + ": written for other inputs");
  // Another build of the program.
  std::string other = good;
  other.replace(other.find("program ") + 8, 4, "0000");
  test::write_text(ckpt, other);
  refused("", ckpt + ": written by another build of tetcontact");
  // A damaged file named on its own: one byte of its data changed, or its end cut off.
  other = good;
  other[other.size() - 100] ^= 0x55;
  test::write_text(ckpt, other);
  const auto refused_file = [&](const std::string& why) {
    const auto r = test::run_cli(args + " --restart " + quote(ckpt), dir.str());
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find(why), std::string::npos) << r.err;
    EXPECT_EQ(files_in(cut), before) << "nothing written";
  };
  refused_file(ckpt + ": damaged: its data does not match its checksum");
  test::write_text(ckpt, good.substr(0, good.size() - 10));
  refused_file(ckpt + ": damaged");
  // --restart goes on in the run's own folder.
  test::write_text(ckpt, good);
  refused(" --out " + quote(dir / "elsewhere"), "--restart goes on in the run's own folder");
  EXPECT_FALSE(fs::exists(dir / "elsewhere"));
  // A folder without checkpoints.
  fs::create_directories(dir / "empty");
  const auto none = test::run_cli(args + " --restart " + quote(dir / "empty"), dir.str());
  EXPECT_EQ(none.code, 2);
  EXPECT_NE(none.err.find("no checkpoint to restart from"), std::string::npos) << none.err;
  // In a folder, a damaged newest checkpoint (a crash before the disk had it) gives way to the
  // one before, with a warning; then the run has ended and is not restarted.
  other = good;
  other[other.size() - 100] ^= 0x55;
  test::write_text(ckpt, other);
  const auto r = test::run_cli(args + " --restart " + quote(cut), dir.str());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find(ckpt + ": damaged: its data does not match its checksum: going on from "
                              "the one before"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("restarting from " + cut + "/checkpoints/step_0000000100.ckpt"),
            std::string::npos)
      << r.err;
  EXPECT_TRUE(fs::exists(cut + "/summary.json"));
  const auto again = test::run_cli(args + " --restart " + quote(cut), dir.str());
  EXPECT_EQ(again.code, 2);
  EXPECT_NE(again.err.find("the run there has ended"), std::string::npos) << again.err;
}

// A mesh file the case reads is not in the inputs' hash: the checkpoint holds the mesh's own
// hash, and a mesh file changed since (the same counts of nodes and tets) is refused.
TEST(Checkpoint, ACheckpointOfAnotherMeshIsRefused) {
  test::TempDir dir("checkpoint-mesh");
  fs::create_directories(dir / "cases");
  fs::create_directories(dir / "meshes");
  fs::copy_file(test::source_path("data/cases/two-blocks-msh.yaml"), dir / "cases/blocks.yaml");
  for (const char* m : {"two-blocks-v41.msh", "two-blocks-v22.msh"})
    fs::copy_file(test::source_path(std::string("data/meshes/") + m), dir / "meshes/" + m);
  const std::string args = "run " + quote(dir / "cases/blocks.yaml") +
                           " --quiet --set end_time=2.0e-5 --set output.checkpoint.steps=5";
  const std::string cut = dir / "cut";
  ASSERT_EQ(run_killed_at(12, args + " --out " + quote(cut), dir.str()).code, 137);
  ASSERT_TRUE(fs::exists(cut + "/checkpoints/step_0000000010.ckpt"));
  // The right block's nodes moved by a part in a million along x.
  const std::string path = dir / "meshes/two-blocks-v22.msh";
  std::istringstream in(test::read_text(path));
  std::string out, line;
  int nodes = -1;
  while (std::getline(in, line)) {
    if (nodes > 0) {
      std::istringstream f(line);
      long id;
      double x, y, z;
      f >> id >> x >> y >> z;
      std::ostringstream moved;
      moved.precision(17);
      moved << id << ' ' << x * (1 + 1e-6) << ' ' << y << ' ' << z;
      line = moved.str();
      --nodes;
    } else if (nodes == -2) {
      nodes = std::stoi(line);
    }
    if (line == "$Nodes") nodes = -2;
    out += line + "\n";
  }
  EXPECT_EQ(nodes, 0);
  test::write_text(path, out);
  const auto r = test::run_cli(args + " --restart " + quote(cut), dir.str());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("written on another mesh"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(cut + "/summary.json"));
}

// output.checkpoint's keys, each checked with the key named.
TEST(Checkpoint, BadCheckpointKeysAreNamed) {
  test::TempDir dir("checkpoint-keys");
  for (const auto& [set, why] : std::vector<std::pair<std::string, std::string>>{
           {"output.checkpoint.steps=0", "key 'output.checkpoint.steps': must be at least 1"},
           {"output.checkpoint.interval=-1", "output.checkpoint.interval"},
           {"output.checkpoint={interval: 1.0e-6, steps: 10}", "not both"},
           {"output.checkpoint={keep: 3}", "give `interval`"},
           {"output.checkpoint={steps: 10, keep: 0}",
            "key 'output.checkpoint.keep': must be from 1 to 1000"},
           {"output.checkpoint={steps: 10, every: 3}", "output.checkpoint.every"}}) {
    const auto r = test::run_cli("check " + quote(k_spall) + " --set " + quote(set), dir.str());
    EXPECT_EQ(r.code, 2) << set;
    EXPECT_NE(r.err.find(why), std::string::npos) << set << ": " << r.err;
  }
}
