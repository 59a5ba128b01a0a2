// The aluminium Taylor rod made of SPH particles only: the particles' strength, through the one
// material update the tets call, against the rod's tet twin and the measured final length.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "../validation/case_run.hpp"

namespace tc {
namespace {

// House et al. (1995), 6061-T6 (data/validation/taylor-tests.csv): D0 7.595 mm, L0 11.39 mm,
// 339 m/s, measured Lf 8.3 mm. The quarter rod of data/cases/taylor.yaml on 6 × 18 cells.
const double k_l0 = 11.39e-3, k_lf_measured = 8.3e-3;

std::vector<std::string> row(const std::vector<std::string>& more = {}) {
  std::vector<std::string> sets{"parameters.D0=7.595e-3", "parameters.L0=11.39e-3",
                                "parameters.v=339", "parameters.nc=6", "parameters.na=18"};
  sets.insert(sets.end(), more.begin(), more.end());
  return sets;
}

// The highest and the lowest particle centre.
std::pair<double, double> ends(const State& st) {
  double top = -std::numeric_limits<double>::infinity(), foot = -top;
  for (Index i = 0; i < st.sph.size(); ++i) {
    top = std::max(top, st.x[st.first_particle + i].z());
    foot = std::min(foot, st.x[st.first_particle + i].z());
  }
  return {top, foot};
}

struct ParticleRod {
  double length = 0.0;  // m
  long particles = 0, steps = 0;
  double balance_error_max = 0.0, momentum_error = 0.0;
  double seconds = 0.0;  // setup and run, wall clock
};

// Every cell of the rod made a particle before the first step; the anvil meets the particles
// as spheres of their radius. The rod's rear end stays rigid, so its final length is L0 less
// the rear particles' travel, and plus the foot's (the run ends after the rod leaves the anvil).
ParticleRod particle_rod(const std::vector<std::string>& sets) {
  std::vector<std::string> all = row(sets);
  all.push_back("fracture={enabled: true, debris: sph, erosion_step_ratio: 0}");
  const auto start = std::chrono::steady_clock::now();
  const Case c = load_case(test::source_path("data/cases/taylor.yaml"), all);
  Simulation sim(build_model(c), solver_settings(c));
  std::vector<Index> cells(static_cast<std::size_t>(sim.model().mesh.tet_count()));
  for (std::size_t t = 0; t < cells.size(); ++t) cells[t] = static_cast<Index>(t);
  sim.convert_cells(cells);
  const auto [top0, foot0] = ends(sim.state());
  while (!sim.done()) sim.step();
  ParticleRod r;
  const auto [top1, foot1] = ends(sim.state());
  r.length = k_l0 + (top1 - top0) - (foot1 - foot0);
  r.particles = sim.state().sph.size();
  r.steps = sim.state().step;
  r.balance_error_max = sim.balance_error_max();
  r.momentum_error = momentum_error(sim.first_sample(), sim.last_sample());
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

// Measured (6 × 18 cells, 972 particles, 2,157 steps, 26.6 s; the tets' 0.3 s): Lf 8.53 mm
// against the tets' 8.45 and the measured 8.3 (+0.9 %, +2.7 %). With bilinear strength at
// 0.1 GPa in place of Steinberg–Guinan's (Y0 0.29 GPa) the rod of particles ends at 6.07 mm
// (−27 %): the strength the particles carry holds its length. The largest balance error,
// 1.4e-4 (the tets' rod: 1.1e-4); 7.9e-3 with the pairs' heat booked at the forces' kick
// alone, not at the velocities the anvil leaves the particles it holds.
TEST(SphTaylor, AluminiumRodOfParticlesKeepsItsTetTwinsAndTheMeasuredLength) {
  const test::CaseRun tets = test::run_case("data/cases/taylor.yaml", row());
  const double tet_length = tets.measured("final length");
  const ParticleRod rod = particle_rod({});
  const ParticleRod weak =
      particle_rod({"materials.rod.strength=bilinear", "materials.rod.yield_stress=0.1e9"});
  std::printf(
      "Lf: particles %.4f mm (%ld particles, %ld steps, %.1f s, balance %.2g), "
      "tets %.4f mm (%.1f s, balance %.2g), measured %.4f mm; bilinear at 0.1 GPa: "
      "%.4f mm\n",
      1e3 * rod.length, rod.particles, rod.steps, rod.seconds, rod.balance_error_max,
      1e3 * tet_length, tets.seconds, tets.balance_error_max, 1e3 * k_lf_measured,
      1e3 * weak.length);
  EXPECT_EQ(rod.particles, tets.tets);
  EXPECT_NEAR(rod.length / k_lf_measured, 1.0, 0.05);
  EXPECT_NEAR(rod.length / tet_length, 1.0, 0.05);
  EXPECT_LT(weak.length / k_lf_measured, 0.95);
  EXPECT_LT(rod.momentum_error, 1e-12);
  EXPECT_LT(rod.balance_error_max, 1e-3);
}

// fracture.sph.step_factor reaches the particles' stable step: the rod made particles before
// its first step, every particle at the rod's velocity (no pair approaches), steps at k h /
// (c + 1.2 α c) times the cfl; twice the factor, twice the step.
TEST(SphTaylor, TheStepFactorSetsTheParticlesStep) {
  std::vector<double> steps;
  for (const char* factor : {"0.6", "1.2"}) {
    std::vector<std::string> sets =
        row({"fracture={enabled: true, debris: sph, erosion_step_ratio: 0}",
             std::string("fracture.sph.step_factor=") + factor});
    const Case c = load_case(test::source_path("data/cases/taylor.yaml"), sets);
    Simulation sim(build_model(c), solver_settings(c));
    std::vector<Index> cells(static_cast<std::size_t>(sim.model().mesh.tet_count()));
    for (std::size_t t = 0; t < cells.size(); ++t) cells[t] = static_cast<Index>(t);
    sim.convert_cells(cells);
    steps.push_back(sim.state().dt);
  }
  EXPECT_GT(steps[0], 0.0);
  EXPECT_NEAR(steps[1] / steps[0], 2.0, 1e-12);
}

}  // namespace
}  // namespace tc
