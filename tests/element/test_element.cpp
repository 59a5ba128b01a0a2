// Constant-strain tetrahedra: the patch test and the element kernel against exact results.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <set>
#include <stdexcept>
#include <string>

#include <Eigen/Eigenvalues>

#include "../solver/solver_fixture.hpp"
#include "tetcontact/element/element.hpp"
#include "tetcontact/io/case.hpp"
#include "tetcontact/solver/simulation.hpp"

using namespace tc;

namespace {

// A distorted 3×3×3 box: interior nodes moved so the patch is irregular.
TetMesh distorted_box() {
  TetMesh mesh = make_box(Vec3(1, 1, 1), {3, 3, 3}, HexSplit::six);
  for (Vec3& p : mesh.x) {
    if ((p.array().abs() < 0.49).all())
      p += 0.05 * Vec3(std::sin(7 * p.y()), std::cos(5 * p.z()), std::sin(3 * p.x()));
  }
  return mesh;
}

}  // namespace

TEST(Element, FaceAreaVectorsSumToZeroAndGiveShapeGradients) {
  const Vec3 x0(0.1, 0.2, 0.3), x1(1.3, 0.1, 0.2), x2(0.2, 1.1, 0.4), x3(0.3, 0.4, 0.9);
  const auto a = face_area_vectors(x0, x1, x2, x3);
  EXPECT_NEAR((a[0] + a[1] + a[2] + a[3]).norm(), 0.0, 1e-15);
  // ∇N_i = −a_i/(3V) reproduces a linear field exactly: Σ_i φ(x_i) ∇N_i = ∇φ.
  const double V = tet_signed_volume(x0, x1, x2, x3);
  const Vec3 g(0.7, -1.3, 2.1);
  Vec3 grad = Vec3::Zero();
  const std::array<Vec3, 4> x{x0, x1, x2, x3};
  for (int i = 0; i < 4; ++i) grad += (g.dot(x[i]) + 5.0) * (-a[i] / (3.0 * V));
  EXPECT_NEAR((grad - g).norm(), 0.0, 1e-13);
}

// Patch test: a linear velocity field (uniform strain rate) on a distorted mesh gives the same
// stress in every tet, equal to the exact update; under that uniform stress the internal
// force on every interior node vanishes. Both pressure formulations pass it.
class Patch : public ::testing::TestWithParam<bool> {};

TEST_P(Patch, UniformStrainGivesUniformStress) {
  const Material mat = test::aluminium();
  Model model = test::single_body_model(distorted_box(), mat);
  model.element.average_nodal_pressure = {static_cast<char>(GetParam())};
  Mat3 L;  // symmetric: no spin
  L << 1.0, 0.2, -0.1, 0.2, -0.5, 0.3, -0.1, 0.3, 0.4;
  L *= 1e-3;
  for (std::size_t i = 0; i < model.mesh.x.size(); ++i)
    model.initial_velocity[i] = L * model.mesh.x[i];
  State st = initial_state(model);
  const double tau = 1e-3;                  // strain 1e-6: μ = V0/V − 1 well above round-off
  for (Vec3& p : st.x) p += tau * (L * p);  // x^{n+1} = x^n + τ U
  ElementScratch scratch;
  update_material(model.mesh.tets, model.materials, model.element, tau, st, scratch);
  // Exact: the velocity gradient over the mid-step geometry (I + τL/2)X is
  // L_mid = L (I + τL/2)⁻¹ (symmetric: no spin); s = 2G τ dev L_mid; p = K μ with
  // μ = V0/V − 1 of the uniform volume change det(I + τL).
  const Mat3 L_mid = L * (Mat3::Identity() + 0.5 * tau * L).inverse();
  const Mat3 s_exact =
      2.0 * mat.shear_modulus * tau * (L_mid - L_mid.trace() / 3.0 * Mat3::Identity());
  const double mu = 1.0 / (Mat3::Identity() + tau * L).determinant() - 1.0;
  const double p_exact = mat.bulk_modulus * mu;
  for (std::size_t t = 0; t < st.s.size(); ++t) {
    EXPECT_NEAR((to_mat3(st.s[t]) - s_exact).norm(), 0.0, 1e-9 * s_exact.norm()) << "tet " << t;
    EXPECT_NEAR(st.p[t], p_exact, 1e-7 * std::abs(p_exact)) << "tet " << t;
  }
  // The forces of the fused pass equal those of compute_forces on the same state.
  const std::vector<Vec3> fused = st.f;
  compute_forces(model.mesh.tets, model.element, st, scratch);
  for (std::size_t i = 0; i < st.x.size(); ++i)
    EXPECT_NEAR((fused[i] - st.f[i]).norm(), 0.0, 1e-12 * (1.0 + st.f[i].norm())) << "node " << i;
  const Surface& s = model.surfaces.front();
  double fmax = 0.0;
  for (std::size_t i = 0; i < st.x.size(); ++i) fmax = std::max(fmax, st.f[i].norm());
  int interior = 0;
  for (std::size_t i = 0; i < st.x.size(); ++i) {
    if (std::binary_search(s.nodes.begin(), s.nodes.end(), static_cast<Index>(i))) continue;
    EXPECT_NEAR(st.f[i].norm(), 0.0, 1e-6 * fmax) << "interior node " << i;
    ++interior;
  }
  EXPECT_EQ(interior, 8);  // the 2×2×2 interior lattice nodes of a 3×3×3 box
  EXPECT_GT(fmax, 0.0);
}

INSTANTIATE_TEST_SUITE_P(Pressure, Patch, ::testing::Values(false, true),
                         [](const auto& info) { return info.param ? "nodal" : "per_tet"; });

TEST(Element, ForcesOfUniformPressureBalanceTractions) {
  // Uniform pressure p in a cube: nodal forces on each face sum to p A n (the traction).
  const Material mat = test::aluminium();
  Model model = test::single_body_model(make_box(Vec3(2, 2, 2), {2, 2, 2}, HexSplit::twelve), mat);
  State st = initial_state(model);
  for (double& p : st.p) p = 1e6;
  ElementScratch scratch;
  const ForceResult r = compute_forces(model.mesh.tets, model.element, st, scratch);
  Vec3 on_right = Vec3::Zero(), total = Vec3::Zero();
  for (std::size_t i = 0; i < st.x.size(); ++i) {
    total += st.f[i];
    if (std::abs(st.x[i].x() - 1.0) < 1e-12) on_right += st.f[i];
  }
  EXPECT_NEAR(total.norm(), 0.0, 1e-6);
  EXPECT_NEAR(on_right.x(), 4e6, 1e-3);
  // Stable step at rest: the smallest altitude (3V over the largest face's area) of any tet
  // over the dilatational wave speed, computed here by brute force over the 24 tets.
  double h_min = 1e300;
  for (const Tet& k : model.mesh.tets) {
    const Vec3 &a = st.x[k[0]], &b = st.x[k[1]], &c = st.x[k[2]], &d = st.x[k[3]];
    const double vol = std::abs((b - a).cross(c - a).dot(d - a)) / 6.0;
    double area = 0.0;
    for (const auto& [p, q, w] : {std::array<Vec3, 3>{a, b, c}, std::array<Vec3, 3>{a, b, d},
                                  std::array<Vec3, 3>{a, c, d}, std::array<Vec3, 3>{b, c, d}})
      area = std::max(area, 0.5 * (q - p).cross(w - p).norm());
    h_min = std::min(h_min, 3.0 * vol / area);
  }
  EXPECT_NEAR(r.dt_stable / (h_min / mat.wave_speed()), 1.0, 1e-12);
}

// The nodal forces are each cell's corner forces f_i = σ a_i / 3 (f_0 = −(f_1 + f_2 + f_3))
// added cell by cell in ascending order, cells turned into particles left out: an irregular
// box with a different stress in every cell, against that scatter done here.
TEST(Element, NodalForcesAreTheCellsCornerForcesAddedInCellOrder) {
  Model model = test::single_body_model(distorted_box(), test::aluminium());
  State st = initial_state(model);
  const std::size_t cells = model.mesh.tets.size();
  for (std::size_t t = 0; t < cells; ++t) {
    const double u = static_cast<double>(t);
    st.s[t] = Sym6{1e6 * std::sin(u),     2e6 * std::cos(u),     -3e6 * std::sin(2 * u),
                   4e5 * std::cos(3 * u), 5e5 * std::sin(5 * u), -6e5 * std::cos(7 * u)};
    st.p[t] = 1e7 * std::cos(11 * u);
    st.q[t] = 1e5 * (t % 3);
  }
  // A step with every cell, then some cells turned into particles: their corner forces from
  // that step must not reach the nodes.
  ElementScratch scratch;
  compute_forces(model.mesh.tets, model.element, st, scratch);
  for (std::size_t t = 5; t < cells; t += 17) st.damage[t] = Damage::particle;
  compute_forces(model.mesh.tets, model.element, st, scratch);
  std::vector<Vec3> scatter(st.x.size(), Vec3::Zero());
  double largest = 0.0;
  for (std::size_t t = 0; t < cells; ++t) {
    if (st.damage[t] == Damage::particle) continue;
    const Tet& k = model.mesh.tets[t];
    const std::array<Vec3, 4> a = face_area_vectors(st.x[k[0]], st.x[k[1]], st.x[k[2]], st.x[k[3]]);
    const Mat3 sigma = to_mat3(st.s[t]) - (st.p[t] + st.q[t]) * Mat3::Identity();
    Vec3 f0 = Vec3::Zero();
    for (int i = 1; i < 4; ++i) {
      const Vec3 fi = sigma * a[i] / 3.0;
      scatter[k[i]] += fi;
      f0 -= fi;
      largest = std::max(largest, fi.norm());
    }
    scatter[k[0]] += f0;
  }
  ASSERT_GT(largest, 0.0);
  for (std::size_t n = 0; n < st.x.size(); ++n)
    EXPECT_LE((st.f[n] - scatter[n]).norm(), 1e-12 * largest) << "node " << n;
}

// Jaumann rate under rigid rotation: a stressed cube spun through a full turn in 1,000 exact
// rotation steps keeps its principal stresses to 1e-10 relative, and its stress is the
// initial one rotated (σ = R σ0 Rᵀ). The mid-step velocity gradient of an exact rotation is
// skew (Cayley), and the Hughes–Winget update rotates by exactly that rotation.
TEST(Element, SpinningStressedCubeKeepsPrincipalValues) {
  const Material mat = test::aluminium();
  Model model =
      test::single_body_model(make_box(Vec3(0.01, 0.01, 0.01), {2, 2, 2}, HexSplit::six), mat);
  State st = initial_state(model);
  // A consistent initial state: compressed by 0.1 % (pressure from the EOS) plus a deviator.
  for (Vec3& p : st.x) p *= 0.999;
  const double mu0 = 1.0 / (0.999 * 0.999 * 0.999) - 1.0;
  Mat3 s0;
  s0 << 80, 30, -10, 30, -50, 20, -10, 20, -30;
  s0 *= 1e6;
  for (std::size_t t = 0; t < st.s.size(); ++t) {
    st.s[t] = to_sym6(s0);
    st.p[t] = mat.bulk_modulus * mu0;
    st.vol[t] = tet_signed_volume(st.x[model.mesh.tets[t][0]], st.x[model.mesh.tets[t][1]],
                                  st.x[model.mesh.tets[t][2]], st.x[model.mesh.tets[t][3]]);
  }
  const Mat3 sigma0 = s0 - st.p[0] * Mat3::Identity();
  const int steps = 1000;
  const double omega = 2e4, tau = 2.0 * M_PI / omega / steps;  // one turn
  const Vec3 axis = Vec3(1, 2, 3).normalized();
  const Mat3 R = Eigen::AngleAxisd(omega * tau, axis).toRotationMatrix();
  ElementScratch scratch;
  for (int n = 0; n < steps; ++n) {
    for (std::size_t i = 0; i < st.x.size(); ++i) {
      const Vec3 next = R * st.x[i];
      st.v[i] = (next - st.x[i]) / tau;
      st.x[i] = next;
    }
    update_material(model.mesh.tets, model.materials, model.element, tau, st, scratch);
  }
  Eigen::SelfAdjointEigenSolver<Mat3> e0(sigma0);
  const Mat3 R_total = Eigen::AngleAxisd(omega * tau * steps, axis).toRotationMatrix();
  double worst = 0.0;
  for (std::size_t t = 0; t < st.s.size(); ++t) {
    const Mat3 sigma = cauchy_stress(st, static_cast<Index>(t));
    Eigen::SelfAdjointEigenSolver<Mat3> e(sigma);
    worst = std::max(worst, (e.eigenvalues() - e0.eigenvalues()).norm() / sigma0.norm());
    EXPECT_NEAR((sigma - R_total * sigma0 * R_total.transpose()).norm(), 0.0, 1e-9 * sigma0.norm());
  }
  EXPECT_LT(worst, 1e-10);
  EXPECT_EQ(st.eps_p[0], 0.0);
}

TEST(Element, ViscosityZeroInExpansionPositiveInCompression) {
  Model model = test::single_body_model(make_box(Vec3(0.01, 0.01, 0.01), {2, 2, 2}, HexSplit::six),
                                        test::aluminium());
  model.element.viscosity_linear = 0.06;
  model.element.viscosity_quadratic = 1.5;
  for (double sign : {+1.0, -1.0}) {
    State st = initial_state(model);
    const double tau = 1e-8, rate = sign * 1e4;
    for (std::size_t i = 0; i < st.x.size(); ++i) {
      st.v[i] = rate * st.x[i];
      st.x[i] += tau * st.v[i];
    }
    ElementScratch scratch;
    update_material(model.mesh.tets, model.materials, model.element, tau, st, scratch);
    for (std::size_t t = 0; t < st.q.size(); ++t) {
      if (sign > 0) {
        EXPECT_EQ(st.q[t], 0.0);
        EXPECT_EQ(st.w_viscous[t], 0.0);
      } else {
        EXPECT_GT(st.q[t], 0.0);
        EXPECT_GT(st.w_viscous[t], 0.0);  // viscous work heats, never cools
      }
    }
  }
}

TEST(Element, InvertedElementIsReportedWithItsBody) {
  Model model =
      test::single_body_model(make_box(Vec3(1, 1, 1), {2, 2, 2}, HexSplit::six), test::aluminium());
  const Index centre = 13;  // lattice (1,1,1)
  ASSERT_NEAR(model.mesh.x[centre].norm(), 0.0, 1e-15);
  model.initial_velocity[centre] = Vec3(1e12, 0, 0);
  SolverSettings settings;
  settings.end_time = 1e-3;
  Simulation sim(std::move(model), settings);
  try {
    sim.step();
    sim.step();
    FAIL() << "no failure reported";
  } catch (const InvertedElement& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("body 'body', tet"), std::string::npos) << msg;
    EXPECT_NE(msg.find("inverted"), std::string::npos) << msg;
  }
}

// Dobritsa et al.'s failure, per-tet and nodal pressure alike: a uniform stretch whose tension
// stays below σ* leaves cells intact; above it every cell is damaged (no deviator, no tension
// carried) but still carries pressure when compressed; loosened past χ* = 0.03 it is destroyed and
// carries no pressure while loosened, compressed or not, until pressed back below V0.
class Failure : public ::testing::TestWithParam<bool> {};
TEST_P(Failure, SpallDamagesAndLooseningDestroys) {
  Material mat = test::aluminium();  // K = 58.3 GPa: a volumetric strain of 3e-3 is 175 MPa
  const auto model_with = [&](double spall) {
    mat.spall_strength = spall;
    Model m =
        test::single_body_model(make_box(Vec3(0.01, 0.01, 0.01), {2, 2, 2}, HexSplit::six), mat);
    m.element.average_nodal_pressure = {static_cast<char>(GetParam())};
    m.element.fracture = true;
    return m;
  };
  ElementScratch scratch;
  const auto stretch = [&](const Model& m, State& st, double strain) {  // one step, uniform
    const double tau = 1e-8;
    for (std::size_t i = 0; i < st.x.size(); ++i) {
      st.v[i] = (strain / tau) * st.x[i];
      st.x[i] += tau * st.v[i];
    }
    update_material(m.mesh.tets, m.materials, m.element, tau, st, scratch);
  };
  const auto all = [](const State& st, Damage d) {
    return std::all_of(st.damage.begin(), st.damage.end(), [&](Damage x) { return x == d; });
  };
  {
    const Model m = model_with(1e9);
    State st = initial_state(m);
    stretch(m, st, 1e-3);
    EXPECT_TRUE(all(st, Damage::intact));
    EXPECT_LT(st.p[0], -1e8);  // the tension is carried
  }
  const Model m = model_with(1e8);
  State st = initial_state(m);
  stretch(m, st, 1e-3);  // χ = 1 − V0/V = 0.003: damaged, not destroyed
  ASSERT_TRUE(all(st, Damage::damaged));
  for (std::size_t t = 0; t < st.p.size(); ++t) {
    EXPECT_EQ(st.p[t], 0.0);
    EXPECT_EQ(to_mat3(st.s[t]).norm(), 0.0);
  }
  stretch(m, st, -3e-3);  // compressed again: pressure, still no deviator
  EXPECT_TRUE(all(st, Damage::damaged));
  for (std::size_t t = 0; t < st.p.size(); ++t) {
    EXPECT_GT(st.p[t], 1e8);
    EXPECT_EQ(to_mat3(st.s[t]).norm(), 0.0);
  }
  stretch(m, st, 0.03);  // χ ≈ 0.08 > 0.03: destroyed
  ASSERT_TRUE(all(st, Damage::destroyed));
  stretch(m, st, -0.02);  // compressed, but still loosened (V > V0): nothing carried
  for (std::size_t t = 0; t < st.p.size(); ++t) EXPECT_EQ(st.p[t], 0.0);
  stretch(m, st, -0.05);  // pressed back below V0: it resists compression again
  ASSERT_TRUE(all(st, Damage::destroyed));
  for (std::size_t t = 0; t < st.p.size(); ++t) {
    EXPECT_LT(st.vol[t], st.vol0[t]);
    EXPECT_GT(st.p[t], 1e8);
  }
}
INSTANTIATE_TEST_SUITE_P(Pressure, Failure, ::testing::Values(false, true),
                         [](const auto& info) { return info.param ? "nodal" : "per_tet"; });

// Johnson–Cook ductile damage in the element pass: a box of perfectly plastic
// aluminium stretched step by step along x (F = diag(λ, λ^-1/2, λ^-1/2) a step) while its volume
// grows (tension) or shrinks (compression) by J a step. Each step's damage increment is
// Δε̄p / ε_f(σ*, Δε̄p/τ, T), σ* = −p/σ_eq from the step's starting pressure and the returned
// deviator, to round-off; the cell is listed for erosion exactly when D reaches 1; the same
// stretch under compression leaves D far lower (D3 < 0: triaxiality matters, with its sign).
// The increments taken with ε_f at its floor (the law's own ε_f at or below min_strain) are
// summed apart: none for a set whose ε_f stays above the floor; for 6061-T6's set (D1 < 0: its
// ε_f is negative above σ* ≈ 1.35) a faster-growing tension ends failing at the floor, and
// without ductile failure at the floor it keeps only the damage taken above it.
TEST(Element, DuctileDamageIsThePlasticStrainOverTheFailureStrain) {
  Material mat = test::aluminium();
  mat.yield_stress = 300e6;
  mat.ductile_failure = true;
  mat.johnson_cook_failure.d1 = 0.1;
  mat.johnson_cook_failure.d2 = 0.5;
  mat.johnson_cook_failure.d3 = -3.0;
  mat.johnson_cook_failure.d4 = 0.01;
  Model m =
      test::single_body_model(make_box(Vec3(0.01, 0.01, 0.01), {1, 1, 1}, HexSplit::six), mat);
  ElementScratch scratch;
  const double tau = 1e-8;
  struct Pulled {
    int steps = 0;
    double damage = 0.0, floor = 0.0;
    bool listed = false;
  };
  const auto pull = [&](double j, int max_steps, double lambda = 1.002) {
    State st = initial_state(m);
    Mat3 F = Mat3::Zero();
    F.diagonal() << lambda, 1.0 / std::sqrt(lambda), 1.0 / std::sqrt(lambda);
    F *= std::cbrt(j);
    Pulled out;
    const JohnsonCookFailure& f = m.materials[0].johnson_cook_failure;
    JohnsonCookFailure unfloored = f;
    unfloored.min_strain = -1e300;
    for (; out.steps < max_steps && !out.listed; ++out.steps) {
      const std::vector<double> p0 = st.p, e0 = st.eps_p, d0 = st.ductile, temp0 = st.temperature;
      const std::vector<double> floor0 = st.ductile_floor;
      for (std::size_t i = 0; i < st.x.size(); ++i) {
        const Vec3 next = F * st.x[i];
        st.v[i] = (next - st.x[i]) / tau;
        st.x[i] = next;
      }
      const ForceResult r = update_material(m.mesh.tets, m.materials, m.element, tau, st, scratch);
      for (std::size_t t = 0; t < st.p.size(); ++t) {
        const double de = st.eps_p[t] - e0[t];
        const double triax = -p0[t] / von_mises(st.s[t]);
        const bool floored =
            johnson_cook_failure_strain(unfloored, triax, de / tau, temp0[t]) <= f.min_strain;
        const bool counts = !floored || m.materials[0].ductile_failure_at_floor;
        const double expected = de > 0.0 && counts
                                    ? de / johnson_cook_failure_strain(f, triax, de / tau, temp0[t])
                                    : 0.0;
        EXPECT_NEAR(st.ductile[t] - d0[t], expected, 1e-12) << "step " << out.steps << " tet " << t;
        EXPECT_NEAR(st.ductile_floor[t] - floor0[t], floored ? expected : 0.0, 1e-12)
            << "step " << out.steps << " tet " << t;
      }
      out.listed = std::find(r.eroding.begin(), r.eroding.end(), Index{0}) != r.eroding.end();
      EXPECT_EQ(out.listed, st.ductile[0] >= 1.0) << "step " << out.steps;
      out.damage = st.ductile[0];
      out.floor = st.ductile_floor[0];
    }
    return out;
  };
  const Pulled tension = pull(1.0 + 2e-5, 1000);
  EXPECT_TRUE(tension.listed) << "D " << tension.damage << " after " << tension.steps << " steps";
  EXPECT_EQ(tension.floor, 0.0);  // ε_f ≥ D1 = 0.1 everywhere
  const Pulled compression = pull(1.0 - 2e-5, tension.steps);
  EXPECT_FALSE(compression.listed);
  EXPECT_LT(compression.damage, 0.5);

  // 6061-T6's set, without its temperature term (D5 = 0 here: the box is not heated).
  m.materials[0].johnson_cook_failure = {-0.77, 1.45, -0.47, 0.0, 0.0};
  const double lambda = 1.0002;  // slower flow, and a tension that outgrows the deviator
  const Pulled al6061 = pull(1.0 + 1e-4, 1000, lambda);
  EXPECT_TRUE(al6061.listed);
  std::printf("6061-T6's set: failed after %d steps, D %.3f of which at the floor %.3f\n",
              al6061.steps, al6061.damage, al6061.floor);
  EXPECT_GT(al6061.floor, 0.5 * al6061.damage);  // failed mostly at the floor (0.90 of 1.005)
  EXPECT_LT(al6061.floor, al6061.damage);
  // Without ductile failure at the floor the same pull keeps only the damage taken above it
  // (the damage does not load the cell: the path is the same) and does not fail the cell.
  m.materials[0].ductile_failure_at_floor = false;
  const Pulled within_fit = pull(1.0 + 1e-4, al6061.steps, lambda);
  EXPECT_FALSE(within_fit.listed);
  EXPECT_EQ(within_fit.floor, 0.0);
  EXPECT_NEAR(within_fit.damage, al6061.damage - al6061.floor, 1e-12);
}

// The element stage in SIMD lanes (the cells' kinematics, their material update, the averaged
// pressure's pass) gives the scalar path's state bit for bit, in each copy of the lanes this
// processor runs (SSE2, AVX2, AVX-512): every library material with its default laws (each
// strength law and equation of state the library uses), per-tet and averaged pressure, fracture
// on, a cell turned particle and two failed cells among the others, every cell listed eroding
// (the lists' order compared), and a mesh whose cell count is no multiple of the lanes.
TEST(Element, LanesGiveTheScalarPathsState) {
  std::vector<Material> lib = load_material_library(default_material_library());
  ASSERT_GE(lib.size(), 3u);
  for (std::size_t k = 0, n = lib.size(); k < n; ++k)
    if (lib[k].tillotson.big_a >
        0.0) {  // its Tillotson block, as a case's `eos: {type: tillotson}`
      Material m = lib[k];
      m.eos = EosKind::tillotson;
      lib.push_back(m);
    }
  lib.push_back(test::aluminium());
  std::set<int> laws, eoses;
  bool plastic = false;
  const Lanes widest = widest_lanes();
  EXPECT_EQ(set_element_lanes(widest), widest);  // the default
  EXPECT_THROW(set_element_lanes(static_cast<Lanes>(static_cast<int>(widest) + 1)),
               std::invalid_argument);
  const char* names[] = {"scalar", "SSE2", "AVX2", "AVX-512"};
  for (int copy = static_cast<int>(Lanes::sse2); copy <= static_cast<int>(widest); ++copy)
    for (const Material& mat : lib) {
      laws.insert(static_cast<int>(mat.strength));
      eoses.insert(static_cast<int>(mat.eos));
      for (const bool anp : {false, true}) {
        Model model = test::single_body_model(distorted_box(), mat);
        model.element.average_nodal_pressure = {static_cast<char>(anp)};
        model.element.fracture = true;
        Mat3 L;  // compression, shear and spin: yields within the steps
        L << -3.0, 1.5, 0.4, -0.7, 1.0, 0.8, 0.2, -0.6, 1.2;
        for (std::size_t i = 0; i < model.mesh.x.size(); ++i)
          model.initial_velocity[i] = L * model.mesh.x[i];
        State lanes = initial_state(model);
        lanes.damage[5] = Damage::particle;
        lanes.damage[2] = Damage::damaged;
        lanes.damage[11] = Damage::destroyed;
        State scalar = lanes;
        // Every cell below the erosion limit: each step lists them all, in the paths' order.
        const std::vector<Index> tet_body(model.mesh.tets.size(), 0);
        model.element.erode_dt2 = {1e30};
        model.element.tet_body = tet_body;
        ElementScratch scratch_lanes, scratch_scalar;
        const double tau = 1e-3;
        for (int step = 0; step < 6; ++step) {
          for (State* st : {&lanes, &scalar})
            for (std::size_t i = 0; i < st->x.size(); ++i) st->x[i] += tau * st->v[i];
          const Lanes was = set_element_lanes(static_cast<Lanes>(copy));
          const ForceResult a = update_material(model.mesh.tets, model.materials, model.element,
                                                tau, lanes, scratch_lanes);
          set_element_lanes(Lanes::scalar);
          const ForceResult b = update_material(model.mesh.tets, model.materials, model.element,
                                                tau, scalar, scratch_scalar);
          set_element_lanes(was);
          ASSERT_EQ(a.dt_stable, b.dt_stable)
              << names[copy] << ", " << mat.name << ", step " << step;
          ASSERT_EQ(a.critical_tet, b.critical_tet)
              << names[copy] << ", " << mat.name << ", step " << step;
          ASSERT_EQ(a.eroding, b.eroding) << names[copy] << ", " << mat.name << ", step " << step;
          ASSERT_GE(a.eroding.size(), model.mesh.tets.size() - 1);
        }
        const std::string what = std::string(names[copy]) + ", " + mat.name +
                                 (anp ? ", averaged pressure" : ", per-tet pressure");
        ASSERT_EQ(lanes.s.size(), scalar.s.size());
        for (std::size_t t = 0; t < lanes.s.size(); ++t) {
          ASSERT_EQ(lanes.s[t], scalar.s[t]) << what << ", tet " << t;
          ASSERT_EQ(lanes.p[t], scalar.p[t]) << what << ", tet " << t;
          ASSERT_EQ(lanes.e_int[t], scalar.e_int[t]) << what << ", tet " << t;
          ASSERT_EQ(lanes.eps_p[t], scalar.eps_p[t]) << what << ", tet " << t;
          ASSERT_EQ(lanes.sound2[t], scalar.sound2[t]) << what << ", tet " << t;
          ASSERT_EQ(lanes.trace_d[t], scalar.trace_d[t]) << what << ", tet " << t;
          ASSERT_EQ(lanes.q[t], scalar.q[t]) << what << ", tet " << t;
          ASSERT_EQ(lanes.vol[t], scalar.vol[t]) << what << ", tet " << t;
          ASSERT_EQ(lanes.temperature[t], scalar.temperature[t]) << what << ", tet " << t;
          ASSERT_EQ(lanes.w_plastic[t], scalar.w_plastic[t]) << what << ", tet " << t;
          ASSERT_EQ(lanes.w_viscous[t], scalar.w_viscous[t]) << what << ", tet " << t;
          ASSERT_EQ(lanes.ductile[t], scalar.ductile[t]) << what << ", tet " << t;
          ASSERT_EQ(lanes.ductile_floor[t], scalar.ductile_floor[t]) << what << ", tet " << t;
          ASSERT_EQ(lanes.damage[t], scalar.damage[t]) << what << ", tet " << t;
          plastic = plastic || lanes.eps_p[t] > 0.0;
        }
        for (std::size_t i = 0; i < lanes.f.size(); ++i)
          ASSERT_TRUE(lanes.f[i] == scalar.f[i]) << what << ", node " << i;
      }
    }
  EXPECT_TRUE(plastic);                          // the strength laws' returns ran
  EXPECT_EQ(laws.size(), 3u);                    // bilinear, Johnson–Cook, Steinberg–Guinan
  EXPECT_GE(eoses.size(), 2u);                   // Mie–Grüneisen and Tillotson at least
  EXPECT_EQ(set_element_lanes(widest), widest);  // each run put the setting back
}
