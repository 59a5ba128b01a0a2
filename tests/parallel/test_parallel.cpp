// Threads change who computes, never what: the block helpers give the same sums, minima and
// lists for any thread count, and the whole run gives the same bytes (frames, particles,
// history) on 1, 2 and 3 threads, contact, edge–edge, walls, fracture and particles included.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "../test_util.hpp"
#include "tetcontact/parallel/parallel.hpp"

using namespace tc;

namespace {

namespace fs = std::filesystem;

// Restores the thread count a test changed.
struct ThreadsGuard {
  int saved = tc::parallel::threads();
  ~ThreadsGuard() { tc::parallel::set_threads(saved); }
};

// Values whose sum depends on the order of addition (1e16 + 1 = 1e16 in doubles).
std::vector<double> order_sensitive(std::size_t n) {
  std::vector<double> v(n);
  for (std::size_t i = 0; i < n; ++i) v[i] = (i % 7 == 0) ? 1e16 * ((i % 2) ? 1 : -1) : 1.0 + i;
  return v;
}

}  // namespace

TEST(Parallel, BlockSumIsTheSameForAnyThreadCountAndEqualsTheBlockOrderSum) {
  ThreadsGuard guard;
  const std::vector<double> v = order_sensitive(100'003);
  // The oracle: partial sums per fixed block, added in block order, computed serially here.
  double oracle = 0.0;
  for (std::size_t b = 0; b * tc::parallel::k_block < v.size(); ++b) {
    double part = 0.0;
    for (std::size_t i = b * tc::parallel::k_block;
         i < std::min(v.size(), (b + 1) * tc::parallel::k_block); ++i)
      part += v[i];
    oracle += part;
  }
  double plain = 0.0;
  for (double x : v) plain += x;
  ASSERT_NE(plain, oracle);  // the data do tell orders of addition apart
  for (int n : {1, 2, 3, 8}) {
    tc::parallel::set_threads(n);
    const double s = tc::parallel::sum_blocks<double>(v.size(), [&](std::size_t b, std::size_t e) {
      double part = 0.0;
      for (std::size_t i = b; i < e; ++i) part += v[i];
      return part;
    });
    EXPECT_EQ(s, oracle) << n << " threads";
  }
}

TEST(Parallel, TheLowestFailingBlocksExceptionIsRethrown) {
  ThreadsGuard guard;
  for (int n : {1, 3}) {
    tc::parallel::set_threads(n);
    try {
      tc::parallel::for_each(50'000, [](std::size_t i) {
        if (i == 7'777 || i == 3'001 || i == 40'000) throw std::runtime_error(std::to_string(i));
      });
      ADD_FAILURE() << "nothing thrown";
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "3001") << n << " threads";  // what a serial loop throws first
    }
  }
}

TEST(Parallel, ThreadCountFollowsTheSetting) {
  ThreadsGuard guard;
  tc::parallel::set_threads(3);
  EXPECT_EQ(tc::parallel::threads(), 3);
  tc::parallel::set_threads(0);  // all cores
  EXPECT_EQ(tc::parallel::threads(), tc::parallel::hardware_threads());
  EXPECT_GE(tc::parallel::hardware_threads(), 1);
}

namespace {

// Runs a case on 1, 2 and 3 threads; every frame, particle frame and the history must be the
// same bytes. Returns the 1-thread summary for the caller's checks that the run did something.
test::Json same_on_any_thread_count(const std::string& name, const std::string& case_file,
                                    const std::string& sets) {
  test::TempDir dir("threads-" + name);
  for (int n : {1, 2, 3}) {
    const auto r = test::run_cli("run '" + test::source_path(case_file) + "' --quiet --threads " +
                                     std::to_string(n) + " " + sets + " --out '" +
                                     dir / std::to_string(n) + "'",
                                 dir.str());
    EXPECT_EQ(r.code, 0) << r.err;
  }
  const fs::path one = fs::path(dir.str()) / "1";
  const test::Json summary = test::read_json((one / "summary.json").string());
  EXPECT_EQ(test::number(summary, "/threads"), 1);
  int frames = 0;
  for (const auto& e : fs::directory_iterator(one)) {
    if (e.path().extension() != ".vtu") continue;
    ++frames;
    for (const char* n : {"2", "3"})
      EXPECT_TRUE(test::read_text(e.path().string()) ==
                  test::read_text((fs::path(dir.str()) / n / e.path().filename()).string()))
          << name << ": " << e.path().filename() << " differs on " << n << " threads";
  }
  EXPECT_GT(frames, 1);
  for (const char* n : {"2", "3"}) {
    EXPECT_EQ(test::history_without_timings(one / "history.csv"),
              test::history_without_timings(fs::path(dir.str()) / n / "history.csv"))
        << name << " on " << n << " threads";
    const test::Json other = test::read_json((fs::path(dir.str()) / n / "summary.json").string());
    EXPECT_EQ(test::number(other, "/threads"), std::stoi(n));
    for (const char* key : {"/steps", "/energy/balance_error_max", "/momentum/relative_error"})
      EXPECT_EQ(test::number(summary, key), test::number(other, key)) << name << key;
  }
  return summary;
}

}  // namespace

TEST(Threads, CubesEdgeContactIsBitIdenticalOn1To3Threads) {
  const test::Json s = same_on_any_thread_count("cubes", "data/cases/cubes-edge.yaml", "");
  EXPECT_GT(test::number(s, "/contact/edge_edge"), 0);
}

TEST(Threads, VerifiedStepsWithZonesAreBitIdenticalOn1To3Threads) {
  // The cubes without edge contact: the verification fails pairs, extra passes, steps taken
  // again shorter and rigid and translated impact zones remove them.
  const test::Json s = same_on_any_thread_count(
      "verified", "data/cases/cubes-edge.yaml",
      "--set contact.verify=true --set contact.edge_edge=false --set diagnostics.every_step=true");
  EXPECT_GT(test::number(s, "/contact/verification/step_cuts"), 0);
  EXPECT_GT(test::number(s, "/contact/verification/impact_zones"), 0);
  EXPECT_GT(test::number(s, "/contact/verification/translated_zones"), 0);
}

TEST(Threads, CoarseCylindersWithEdgeEdgeAreBitIdenticalOn1To3Threads) {
  const test::Json s = same_on_any_thread_count(
      "cylinders", "data/cases/cylinders.yaml",
      "--set contact.edge_edge=true --set bodies.0.mesh.cylinder.cells_across=8 "
      "--set bodies.0.mesh.cylinder.cells_axial=8 --set bodies.1.mesh.cylinder.cells_across=4 "
      "--set bodies.1.mesh.cylinder.cells_axial=4");
  EXPECT_GT(test::number(s, "/contact/edge_edge"), 0);
  EXPECT_GT(test::number(s, "/contact/node_face"), 0);
}

TEST(Threads, CoarseBallPlateWithFractureAndParticlesIsBitIdenticalOn1To3Threads) {
  const test::Json s = same_on_any_thread_count(
      "ball-plate", "data/cases/ball-plate.yaml",
      "--set bodies.0.mesh.sphere.cells_across=8 --set 'bodies.1.mesh.box.cells=[24,24,2]' "
      "--set end_time=2.0e-6");
  EXPECT_GT(test::number(s, "/fracture/particles"), 100);
  EXPECT_GT(test::number(s, "/fracture/particle_contacts"), 100);
  EXPECT_GT(test::number(s, "/contact/node_face"), 0);
}

// SPH debris: the coarse Whipple shot with its debris as SPH particles (their neighbours, mirror
// images, material update, the faces' terms and forces on the threads). The faces met through
// the kernel, the particle contact keeps every centre out of the cells: the penetration probe
// finds none deeper than round-off at any frame (a centre the contact set on a face may lie
// 1e-19 m behind it: measured 2.2e-19 m) and none inside at the end.
TEST(Threads, CoarseWhippleWithSphDebrisIsBitIdenticalOn1To3Threads) {
  const test::Json s = same_on_any_thread_count(
      "whipple-sph", "data/cases/whipple.yaml",
      "--set parameters.hb=1.0e-3 --set parameters.hw=2.0e-3 --set parameters.np=6 "
      "--set parameters.tear=2.0e-6 --set parameters.S=15e-3 --set parameters.ww=30e-3 "
      "--set fracture.debris=sph");
  EXPECT_GT(test::number(s, "/fracture/particles"), 100);
  EXPECT_GT(test::number(s, "/fracture/sph/neighbours_per_particle"), 5);
  EXPECT_GT(test::number(s, "/fracture/sph/faces_per_particle"), 0.5);
  EXPECT_LT(test::number(s, "/penetration/max_particle_depth"), 1e-15);
  EXPECT_EQ(test::number(s, "/penetration/particles_inside_at_end"), 0);
  // The particles' stable step sets most steps (measured: 2,597 of 2,687).
  EXPECT_GT(test::number(s, "/time_step/particle_steps"), 0.5 * test::number(s, "/steps"));
}

TEST(Threads, HertzTestMeshIsBitIdenticalOn1To3Threads) {
  const test::Json s = same_on_any_thread_count(
      "hertz", "data/cases/hertz-spheres.yaml",
      "--set end_time=2.0e-6 --set bodies.0.mesh.sphere.growth=0.3 "
      "--set bodies.1.mesh.sphere.growth=0.3 --set bodies.0.mesh.sphere.cell_size=1.0e-3 "
      "--set bodies.1.mesh.sphere.cell_size=1.0e-3");
  EXPECT_GT(test::number(s, "/contact/node_face"), 0);
}

TEST(Threads, TaylorRodOnAWallWithNodalPressureIsBitIdenticalOn1To3Threads) {
  const test::Json s =
      same_on_any_thread_count("taylor", "data/cases/taylor-copper.yaml",
                               "--set end_time=5.0e-6 --set bodies.0.mesh.cylinder.cells_across=6 "
                               "--set bodies.0.mesh.cylinder.cells_axial=30");
  EXPECT_GT(test::number(s, "/walls/0/max_force"), 0);
}
