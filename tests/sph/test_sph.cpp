// The SPH stage (sph/): its kernel, its neighbour search against brute force, a uniform state
// at rest, conservation in a collision, the shock state of a plate impact against the
// material's Hugoniot and aluminium's measured shocks, and bit-identical threads.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <numbers>
#include <random>
#include <set>
#include <sstream>
#include <tuple>

#include "../test_util.hpp"
#include "sph_run.hpp"
#include "tetcontact/app/setup.hpp"
#include "tetcontact/mesh/symmetry.hpp"
#include "tetcontact/parallel/parallel.hpp"
#include "tetcontact/solver/run_loop.hpp"
#include "tetcontact/solver/simulation.hpp"
#include "tetcontact/sph/kernel.hpp"

using namespace tc;

namespace {

// ∫ W dV = 4π ∫ W r² dr, by Simpson's rule on 2,000 intervals of [0, 2h].
double kernel_integral(double h) {
  const int n = 2000;
  const double b = sph::k_support * h, dr = b / n;
  double s = 0.0;
  for (int i = 0; i <= n; ++i) {
    const double r = i * dr, w = (i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0);
    s += w * sph::kernel(r, h) * r * r;
  }
  return 4.0 * std::numbers::pi * s * dr / 3.0;
}

}  // namespace

TEST(Sph, KernelIsNormalisedAndItsSlopeIsItsDerivative) {
  for (double h : {1e-4, 0.37, 2.0}) {
    EXPECT_NEAR(kernel_integral(h), 1.0, 1e-9) << h;
    EXPECT_EQ(sph::kernel(2.0 * h, h), 0.0);
    EXPECT_EQ(sph::kernel_slope(2.0 * h, h), 0.0);
    for (double q : {0.1, 0.5, 0.99, 1.0, 1.01, 1.5, 1.9}) {
      const double r = q * h, d = 1e-6 * h;
      const double fd = (sph::kernel(r + d, h) - sph::kernel(r - d, h)) / (2.0 * d);
      EXPECT_NEAR(sph::kernel_slope(r, h), fd, 1e-6 * std::abs(fd) + 1e-9 / std::pow(h, 4))
          << "q = " << q;
      EXPECT_LT(sph::kernel_slope(r, h), 0.0);
    }
  }
  // The gradient is antisymmetric to the bit.
  const Vec3 r(0.3, -0.1, 0.7);
  EXPECT_EQ(sph::kernel_gradient(r, 0.5), -sph::kernel_gradient(-r, 0.5));
}

// Random particles in a box with three symmetry planes (and one opposite plane): the lists made
// from the candidates of the detection's broadphase (the engine's, over the particles alone), and
// from every pair, equal a brute-force search over every particle and every image.
TEST(Sph, NeighboursAreTheBruteForcePairsWithMirrorImages) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0), hs(0.04, 0.08);
  const std::vector<sph::MirrorPlane> planes{
      {0, 0.0, 1.0}, {1, 0.0, 1.0}, {2, 0.0, 1.0}, {0, 1.0, -1.0}};
  const std::size_t n = 600;
  std::vector<Vec3> x(n);
  std::vector<double> h(n);
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = Vec3(u(rng), u(rng), u(rng));
    h[i] = hs(rng);
  }
  const double reach = 1.2;
  std::vector<std::pair<Index, Index>> every;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j) every.emplace_back(i, j);
  State st;
  st.x = x;
  st.particle_radius.assign(n, 0.0);
  st.sph.h = h;
  const Mesh none;
  ContactCandidates detection(none, {},
                              {.broadphase = "grid",
                               .bodies = false,
                               .particles = true,
                               .kernel_reach = reach * sph::k_support});
  std::vector<std::pair<Index, Index>> listed = detection.particles_at(st).edge_edge;
  EXPECT_LT(listed.size(), every.size() / 10);  // the broadphase's pruning
  for (std::vector<std::pair<Index, Index>>* candidates : {&listed, &every}) {
    const sph::Neighbours nb = sph::find_neighbours(x, h, planes, reach, *candidates);
    long pairs = 0, images = 0;
    for (std::size_t i = 0; i < n; ++i) {
      std::set<std::pair<Index, unsigned>> found, expected;
      for (Index e = nb.begin[i]; e < nb.begin[i + 1]; ++e) {
        const Index k = nb.list[e];
        found.insert(k < static_cast<Index>(n)
                         ? std::make_pair(k, 0u)
                         : std::make_pair(nb.ghost_source[k - n], nb.ghost_planes[k - n]));
      }
      for (std::size_t j = 0; j < n; ++j)
        for (unsigned mask = 0; mask < 16; ++mask) {
          if ((mask & 1u) && (mask & 8u)) continue;  // two planes of one axis
          if (mask == 0 && j == i) continue;
          const Vec3 y = mirror_image(x[j], sph::symmetry_planes(planes), static_cast<int>(mask));
          if ((x[i] - y).norm() < reach * 2.0 * 0.5 * (h[i] + h[j]))
            expected.insert({static_cast<Index>(j), mask});
        }
      EXPECT_EQ(found, expected) << "particle " << i;
      pairs += static_cast<long>(expected.size());
      for (const auto& [j, mask] : expected) images += mask != 0;
    }
    EXPECT_GT(pairs, 5 * static_cast<long>(n));
    EXPECT_GT(images, 500);
  }
}

// A block under uniform stress (a pressure and a diagonal deviator, in tension so that the
// artificial stress acts) closed by mirror planes on every side is the inside of an endless
// body: no force on any particle. Open one side and the particles there are pulled.
TEST(Sph, UniformStressInAMirrorBoxExertsNoForce) {
  for (bool open : {false, true}) {
    std::vector<sph::MirrorPlane> planes{
        {0, 0.0, 1.0}, {1, 0.0, 1.0}, {2, 0.0, 1.0}, {1, 6e-3, -1.0}, {2, 6e-3, -1.0}};
    if (!open) planes.push_back({0, 6e-3, -1.0});
    test::ParticleRun run({test::library_material("al6061-t6")}, sph::Options{}, planes);
    run.lattice(Vec3::Zero(), 6, 6, 6, 1e-3, Vec3::Zero());
    for (Index i = 0; i < run.st.sph.size(); ++i) {
      run.st.sph.p[i] = -0.3e9;
      run.st.sph.s[i] = Sym6{0.2e9, -0.1e9, -0.1e9, 0, 0, 0};
    }
    run.forces();
    // The scale of one neighbour's term: m σ/ρ² m |∇W| ~ m σ / (ρ h).
    const double scale = run.st.m[0] * 0.5e9 / (2700.0 * 1.3e-3);
    double largest = 0.0, at_open_face = 0.0;
    for (Index i = 0; i < run.st.sph.size(); ++i) {
      largest = std::max(largest, run.st.f[i].norm());
      if (run.st.x[i][0] > 5e-3) at_open_face = std::max(at_open_face, run.st.f[i].norm());
    }
    if (!open) {
      EXPECT_LT(largest, 1e-12 * scale);
    } else {
      EXPECT_GT(at_open_face, 0.1 * scale);
    }
  }
}

// The particles' stable step at rest (no pair approaching, so μ = 0): k h / (c + 1.2 α c), with
// k the step factor (fracture.sph.step_factor) and c the material's sound speed at rest.
TEST(Sph, StableStepAtRestIsTheStepFactorsCourantLimit) {
  for (double factor : {0.6, 1.3}) {
    sph::Options o;
    o.step_factor = factor;
    test::ParticleRun run({test::library_material("al6061-t6")}, o, {});
    const double dx = 1e-3;
    run.lattice(Vec3::Zero(), 4, 4, 4, dx, Vec3::Zero());
    const sph::StepLimit limit = run.forces();
    const double c = std::sqrt(run.st.sph.sound2[0]), h = 1.3 * dx;
    EXPECT_GT(c, 4000.0);  // aluminium's bulk sound speed, about 5.2 km/s
    EXPECT_NEAR(limit.dt_stable, factor * h / (c + 1.2 * o.alpha * c), 1e-12 * limit.dt_stable)
        << "step factor " << factor;
  }
}

// Two aluminium blocks meet at 1 km/s: momentum kept to round-off; energy (kinetic at the
// whole step, U^{n+1/2} + ½ τ F/m, plus internal, plus the pair heat of that half kick, which the
// next update books) to 5e-4 of the kinetic energy at every step (measured 4.0e-5). Without the
// half kick's heat the kinetic energy runs ahead of the heat by half a step's: 3.3e-3 at most
// while the blocks are crushed (asserted above 1e-3).
TEST(Sph, CollisionKeepsMomentumAndEnergy) {
  test::ParticleRun run({test::library_material("al6061-t6")}, sph::Options{}, {});
  const double dx = 1e-3;
  run.lattice(Vec3(0, 0, 0), 6, 6, 6, dx, Vec3(0, 0, 500.0));
  run.lattice(Vec3(0.5 * dx, 0.3 * dx, 8.7 * dx), 6, 6, 6, dx, Vec3(0, 0, -500.0));
  const Vec3 p0 = run.momentum();
  const double e0 = run.kinetic() + run.internal(), k0 = run.kinetic();
  double mv = 0.0;
  for (std::size_t i = 0; i < run.st.x.size(); ++i) mv += run.st.m[i] * run.st.v[i].norm();
  run.start();
  double worst = 0.0, worst_unbooked = 0.0, kinetic = 0.0;
  while (run.t < 2.7 * dx / 1000.0 + 2.0 * 6 * dx / 5000.0) {
    run.step();
    kinetic = 0.0;
    for (std::size_t i = 0; i < run.st.x.size(); ++i)
      kinetic += 0.5 * run.st.m[i] *
                 (run.st.v[i] + (0.5 * run.dt_prev / run.st.m[i]) * run.st.f[i]).squaredNorm();
    const double pending = 0.5 * run.dt_prev * run.stage.heat_rate();
    worst = std::max(worst, std::abs(kinetic + run.internal() + pending - e0));
    worst_unbooked = std::max(worst_unbooked, std::abs(kinetic + run.internal() - e0));
  }
  std::printf(
      "largest energy error %.2e of the kinetic energy (%.2e without the heat of the "
      "half kick)\n",
      worst / k0, worst_unbooked / k0);
  const Vec3 p1 = run.momentum();
  EXPECT_LT((p1 - p0).norm(), 1e-13 * mv) << (p1 - p0).transpose();
  EXPECT_LT(worst, 5e-4 * k0) << "kinetic " << kinetic << " internal " << run.internal();
  EXPECT_GT(worst_unbooked, 1e-3 * k0);
  // The collision happened: much of the kinetic energy went into the blocks.
  EXPECT_LT(kinetic, 0.5 * k0);
}

namespace {

struct Shock {
  double v_over_v0, pressure;
};

std::vector<Shock> measured(const std::string& source) {
  std::ifstream in(test::source_path("data/validation/aluminium-hugoniot.csv"));
  EXPECT_TRUE(in) << "data/validation/aluminium-hugoniot.csv";
  std::vector<Shock> out;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#' || line.rfind("V_over_V0", 0) == 0) continue;
    if (line.find(source) == std::string::npos) continue;
    std::stringstream ss(line);
    std::string v, p;
    std::getline(ss, v, ',');
    std::getline(ss, p, ',');
    out.push_back({std::stod(v), std::stod(p) * 1e9});
  }
  return out;
}

// The measured pressure at V/V0 = v: a straight line through the six points nearest in V/V0.
double measured_pressure(std::vector<Shock> s, double v) {
  std::sort(s.begin(), s.end(), [&](const Shock& a, const Shock& b) {
    return std::abs(a.v_over_v0 - v) < std::abs(b.v_over_v0 - v);
  });
  s.resize(6);
  double mx = 0, my = 0;
  for (const Shock& p : s) mx += p.v_over_v0 / 6, my += p.pressure / 6;
  double sxy = 0, sxx = 0;
  for (const Shock& p : s) {
    sxy += (p.v_over_v0 - mx) * (p.pressure - my);
    sxx += (p.v_over_v0 - mx) * (p.v_over_v0 - mx);
  }
  return my + sxy / sxx * (v - mx);
}

// The material's own Hugoniot pressure at V/V0 (Mie–Grüneisen with E = ½ p (1 − V/V0)).
double eos_hugoniot(const Material& m, double v) {
  const double eta = 1.0 - v;
  const EosTerms t = eos_terms(m, eta / v);
  return t.a / (1.0 - 0.5 * t.b * eta);
}

// The tets' twin of the particles' plate impact: the shipped 1-D plate impact
// (plate-impact-1d.yaml: a column of cells on rollers against a rigid wall, the symmetry plane of
// a symmetric impact) of 2024-T4 at particle velocity up, run until its shock is 4 mm from the
// wall; (V/V0, p) averaged over the cells between 0.5 mm and 70 % of the way to the shock.
std::pair<double, double> tet_shock_state(const Material& al, double up) {
  const double us = al.c0 + al.s * up, front = 4e-3;
  std::ostringstream end, velocity;
  end << "end_time=" << front / (us - up);
  velocity << "bodies.0.velocity=[0, 0, " << -up << "]";
  static std::vector<Case> keep;
  keep.push_back(load_case(test::source_path("data/cases/plate-impact-1d.yaml"),
                           {"materials.al.from=al2024-t4", end.str(), velocity.str()}));
  Simulation sim(build_model(keep.back()), solver_settings(keep.back()));
  EXPECT_EQ(run_to_end(sim, RunHooks{}), "ok");
  const State& st = sim.state();
  double vv0 = 0.0, p = 0.0;
  int n = 0;
  for (Index t = 0; t < sim.model().mesh.tet_count(); ++t) {
    double z = 0.0;
    for (Index k : sim.model().mesh.tets[t]) z += 0.25 * st.x[k][2];
    if (z < 0.5e-3 || z > 0.7 * front) continue;
    vv0 += st.vol[t] / st.vol0[t];
    p += st.p[t];
    ++n;
  }
  EXPECT_GT(n, 100);
  return {vv0 / n, p / n};
}

}  // namespace

// A symmetric plate impact of 2024-T4 aluminium, particles only, in uniaxial strain (a column
// between mirror planes): behind each shock the material is at rest, and its state lies on the
// material's Hugoniot (p against V/V0 within 2 %; −σzz = ρ0 Us up with Us = c0 + s up within
// 4 %). Against McQueen et al.'s measured shocks of 2024 aluminium the particles' pressure
// is as close as the equation of state itself is at that V/V0 (within 3 % more), and as close
// as the tets' on the same shock (their twin, tet_shock_state; within 3 % more). Measured, the
// particles' error against the measured shocks and the tets': +17.8 and +15.5 % at 1 km/s
// (8 GPa, the edge of the data, where the linear Us–up fit is high), +7.3 and +6.2 % at 2,
// +4.0 and +3.8 % at 4, +1.9 and +2.0 % at 6 km/s.
TEST(Sph, PlateImpactShockStateLiesOnTheHugoniot) {
  const Material al = test::library_material("al2024-t4");
  const std::vector<Shock> mcqueen = measured("McQueen");
  ASSERT_GT(mcqueen.size(), 20u);
  const double dx = 1e-4, w = 4 * dx;
  const int layers = 60;
  for (double speed : {1000.0, 2000.0, 4000.0, 6000.0}) {
    const std::vector<sph::MirrorPlane> column{
        {0, 0.0, 1.0}, {1, 0.0, 1.0}, {0, w, -1.0}, {1, w, -1.0}};
    test::ParticleRun run({al}, sph::Options{}, column);
    run.lattice(Vec3(0, 0, -layers * dx), 4, 4, layers, dx, Vec3(0, 0, 0.5 * speed));
    run.lattice(Vec3(0, 0, 0), 4, 4, layers, dx, Vec3(0, 0, -0.5 * speed));
    const double up = 0.5 * speed, us = al.c0 + al.s * up;
    // Until the shocks have run 40 layers from the interface (at Us − up, the shocked
    // material at rest).
    const double front = 40 * dx;
    run.run_to(front / (us - up));
    double p = 0, szz = 0, vv0 = 0, v = 0;
    int n = 0;
    for (Index i = 0; i < run.st.sph.size(); ++i) {
      const double z = std::abs(run.st.x[i][2]);
      if (z < 8 * dx || z > 0.7 * front) continue;
      p += run.st.sph.p[i];
      szz += run.st.sph.s[i][2] - run.st.sph.p[i];
      vv0 += al.density / run.st.sph.rho[i];
      v = std::max(v, std::abs(run.st.v[i][2]));
      ++n;
    }
    ASSERT_GT(n, 100);
    p /= n, szz /= n, vv0 /= n;
    SCOPED_TRACE(::testing::Message()
                 << speed << " m/s: V/V0 " << vv0 << ", p " << p * 1e-9 << " GPa, -szz "
                 << -szz * 1e-9 << " GPa, " << run.steps << " steps");
    EXPECT_LT(v, 0.05 * up);                          // at rest behind the shocks
    EXPECT_NEAR(vv0, 1.0 - up / us, 0.04 * up / us);  // strength: two waves at 1 km/s
    EXPECT_NEAR(p, eos_hugoniot(al, vv0), 0.02 * p);
    EXPECT_NEAR(-szz, al.density * us * up, 0.04 * al.density * us * up);
    const double pm = measured_pressure(mcqueen, vv0);
    const double eos_error = std::abs(eos_hugoniot(al, vv0) / pm - 1.0);
    EXPECT_LT(std::abs(p / pm - 1.0), eos_error + 0.03) << "measured " << pm * 1e-9 << " GPa";
    const auto [tet_vv0, tet_p] = tet_shock_state(al, up);
    const double tet_error = std::abs(tet_p / measured_pressure(mcqueen, tet_vv0) - 1.0);
    std::printf(
        "%.0f m/s: particles V/V0 %.4f, p %.2f GPa, %+.1f %% of the measured shocks; "
        "tets V/V0 %.4f, p %.2f GPa, %+.1f %%\n",
        speed, vv0, p * 1e-9, 100 * (p / pm - 1.0), tet_vv0, tet_p * 1e-9,
        100 * (tet_p / measured_pressure(mcqueen, tet_vv0) - 1.0));
    EXPECT_LT(std::abs(p / pm - 1.0), tet_error + 0.03) << "tets " << tet_p * 1e-9 << " GPa";
  }
}

// The same collision on 1, 2 and 3 threads (over 2,000 particles: three blocks): every
// position, velocity, pressure and stress bit for bit.
TEST(Sph, ThreadsGiveBitIdenticalResults) {
  std::vector<State> states;
  const int saved = parallel::threads();
  for (int threads : {1, 2, 3}) {
    parallel::set_threads(threads);
    test::ParticleRun run({test::library_material("al6061-t6")}, sph::Options{}, {{0, 0.0, 1.0}});
    const double dx = 1e-3;
    run.lattice(Vec3(0, 0, 0), 12, 12, 8, dx, Vec3(0, 0, 800.0));
    run.lattice(Vec3(0, 0.4 * dx, 8.1 * dx), 12, 12, 8, dx, Vec3(-50.0, 0, -800.0));
    run.start();
    for (int s = 0; s < 40; ++s) run.step();
    states.push_back(run.st);
  }
  parallel::set_threads(saved);
  ASSERT_GT(states[0].sph.size(), 2048);
  for (std::size_t k = 1; k < states.size(); ++k) {
    EXPECT_EQ(states[k].x, states[0].x) << k + 1 << " threads";
    EXPECT_EQ(states[k].v, states[0].v) << k + 1 << " threads";
    EXPECT_EQ(states[k].sph.p, states[0].sph.p) << k + 1 << " threads";
    EXPECT_EQ(states[k].sph.s, states[0].sph.s) << k + 1 << " threads";
    EXPECT_EQ(states[k].particle_energy, states[0].particle_energy) << k + 1 << " threads";
  }
}

namespace {

// A bar of 6061-T6 particles in uniaxial strain (a column between mirror planes), its halves
// pulled apart at ±v0, run for `transits` times the longitudinal wave's transit of its length;
// returns the widest gap between successive layers (the layers' mean positions) seen over the
// run, in layer spacings.
double widest_gap(double v0, double transits, bool fracture) {
  const double dx = 1e-4, w = 4 * dx;
  const int layers = 40;
  sph::Options options;
  options.fracture = fracture;
  test::ParticleRun run({test::library_material("al6061-t6")}, options,
                        {{0, 0.0, 1.0}, {1, 0.0, 1.0}, {0, w, -1.0}, {1, w, -1.0}});
  run.lattice(Vec3(0, 0, 0), 4, 4, layers / 2, dx, Vec3(0, 0, -v0));
  run.lattice(Vec3(0, 0, layers / 2 * dx), 4, 4, layers / 2, dx, Vec3(0, 0, v0));
  // A lattice a little out of true (±2 % of the spacing along the bar), as a real one is.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-0.02 * dx, 0.02 * dx);
  for (Vec3& x : run.st.x) x[2] += u(rng);
  const Material& al = run.materials[0];
  const double end = transits * layers * dx / al.wave_speed();
  run.start();
  double widest = 0.0;
  while (run.t < end) {
    run.step();
    std::vector<double> z(layers, 0.0);
    for (Index i = 0; i < run.st.sph.size(); ++i) z[i / 16] += run.st.x[i][2] / 16;
    std::sort(z.begin(), z.end());
    for (int k = 1; k < layers; ++k) widest = std::max(widest, (z[k] - z[k - 1]) / dx);
  }
  return widest;
}

}  // namespace

// Pulled at half its spall strength (ρ c_L v0 = σ*/2) the bar rings for ten transits in one
// piece (measured: layers at most 1.03 spacings apart); at twice it, it parts within three
// (layers more than 3 spacings apart; 24 after ten), and without fracture it holds there too
// (the check fails without the spall).
// Without the artificial stress this bar also held (1.04 spacings): the remedy's own check is
// Sph.TensileInstabilityIsHeldByTheArtificialStress.
TEST(Sph, BarBelowItsSpallStrengthHoldsAndAboveItParts) {
  const Material al = test::library_material("al6061-t6");
  const double v_spall = al.spall_strength / (al.density * al.wave_speed());
  EXPECT_LT(widest_gap(0.5 * v_spall, 10.0, true), 1.5);
  EXPECT_GT(widest_gap(2.0 * v_spall, 3.0, true), 3.0);
  EXPECT_LT(widest_gap(2.0 * v_spall, 3.0, false), 1.5);
}

namespace {

// A block of 6061-T6 particles inside a mirror box (an endless body), its lattice ±1 % out of
// true, under hydrostatic tension `tension` (the box keeps its volume, so the tension stays),
// run for `transits` longitudinal transits of the box: (the closest pair in spacings, the mean
// pressure).
std::pair<double, double> block_in_tension(double artificial_stress, double tension,
                                           double transits) {
  const double dx = 1e-3;
  const int n = 8;
  const double side = n * dx;
  sph::Options options;
  options.artificial_stress = artificial_stress;
  test::ParticleRun run({test::library_material("al6061-t6")}, options,
                        {{0, 0.0, 1.0},
                         {1, 0.0, 1.0},
                         {2, 0.0, 1.0},
                         {0, side, -1.0},
                         {1, side, -1.0},
                         {2, side, -1.0}});
  run.lattice(Vec3::Zero(), n, n, n, dx, Vec3::Zero());
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.01 * dx, 0.01 * dx);
  for (Vec3& x : run.st.x) x += Vec3(u(rng), u(rng), u(rng));
  const Material& m = run.materials[0];
  const double mu = -tension / (m.density * m.c0 * m.c0);  // p = ρ0 c0² μ = −tension
  for (Index i = 0; i < run.st.sph.size(); ++i) {
    run.st.sph.vol[i] = run.st.sph.vol0[i] / (1.0 + mu);
    run.st.sph.rho[i] = run.st.m[i] / run.st.sph.vol[i];
    run.st.sph.p[i] = -tension;
  }
  run.run_to(transits * side / m.wave_speed());
  double closest = std::numeric_limits<double>::infinity(), p = 0.0;
  for (std::size_t i = 0; i < run.st.x.size(); ++i) {
    for (std::size_t j = i + 1; j < run.st.x.size(); ++j)
      closest = std::min(closest, (run.st.x[i] - run.st.x[j]).norm());
    p += run.st.sph.p[i] / static_cast<double>(run.st.x.size());
  }
  return {closest / dx, p};
}

}  // namespace

// The tensile instability (Swegle et al.): in tension SPH particles clump. A block held at 1 GPa
// of hydrostatic tension keeps its lattice and its tension for fourteen transits with the
// artificial stress (measured: closest pair 0.985 spacings, mean p −0.999 GPa); without it the
// lattice's errors grow and the particles pair up (0.909 spacings, the tension relaxed to
// −0.947 GPa). In compression the same block is stable without it.
TEST(Sph, TensileInstabilityIsHeldByTheArtificialStress) {
  const auto [closest, p] = block_in_tension(0.3, 1e9, 14.0);
  EXPECT_GT(closest, 0.97);
  EXPECT_NEAR(p, -1e9, 0.01e9);
  const auto [closest_off, p_off] = block_in_tension(0.0, 1e9, 14.0);
  EXPECT_LT(closest_off, 0.95);
  EXPECT_GT(p_off, -0.98e9);
  const auto [closest_compressed, p_compressed] = block_in_tension(0.0, -1e9, 14.0);
  EXPECT_GT(closest_compressed, 0.97);
  EXPECT_NEAR(p_compressed, 1e9, 0.02e9);
}

// A hot expanded state carries no tension to spall it (Mie–Grüneisen's Γ0 ρ0 E cancelling
// K μ): a block of 6061-T6 particles at 40 MJ/kg bursts, and its particles swell. An intact
// particle that would grow past 2 V0 fails and is held there as a failed one's solid is.
// Measured (5 × 5 × 5 particles, 1.5 µs, the block parted by then): the largest V/V0 2.000, 81
// particles failed; without the failure past 2 V0, 2.93 and 27 failed.
TEST(Sph, HotExpandedParticlesFailPastTwiceTheirVolume) {
  const double dx = 1e-3;
  sph::Options options;
  options.fracture = true;
  test::ParticleRun run({test::library_material("al6061-t6")}, options, {});
  run.lattice(Vec3::Zero(), 5, 5, 5, dx, Vec3::Zero());
  for (Index i = 0; i < run.st.sph.size(); ++i) run.st.particle_energy[i] = 4e7 * run.st.m[i];
  run.run_to(1.5e-6);
  double largest = 0.0;
  int failed = 0;
  for (Index i = 0; i < run.st.sph.size(); ++i) {
    largest = std::max(largest, run.st.sph.vol[i] / run.st.sph.vol0[i]);
    failed += run.st.sph.damage[i] != Damage::intact;
  }
  std::printf("largest V/V0 %.3f, %d of %ld particles failed\n", largest, failed,
              static_cast<long>(run.st.sph.size()));
  EXPECT_LE(largest, 2.0 * (1.0 + 1e-12));
  EXPECT_GT(failed, 27);
}
