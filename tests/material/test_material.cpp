// Material models against exact results.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <tuple>

#include "tetcontact/element/material_point.hpp"
#include "tetcontact/material/material.hpp"

using namespace tc;

namespace {

Material elastic(double e, double nu, double rho) {
  Material m;
  m.name = "m";
  m.density = rho;
  set_elastic_constants(m, e, nu);
  return m;
}

Material al6061() {  // Steinberg (1996), as in data/materials.yaml
  Material m;
  m.name = "al6061-t6";
  m.density = 2703;
  m.shear_modulus = 27.6e9;
  m.yield_stress = 0.29e9;
  m.eos = EosKind::mie_gruneisen;
  m.c0 = 5240;
  m.s = 1.40;
  m.gamma0 = 1.97;
  m.bulk_modulus = m.density * m.c0 * m.c0;
  return m;
}

Material al_tillotson() {  // the library's aluminium block, [T62]
  Material m = al6061();
  m.eos = EosKind::tillotson;
  m.tillotson = {0.5, 1.63, 75.2e9, 65.0e9, 5.0e6, 3.0e6, 13.9e6, 5.0, 5.0};
  m.bulk_modulus = m.tillotson.big_a;
  return m;
}

double von_mises(const Mat3& s) {
  return std::sqrt(1.5 * s.cwiseProduct(s).sum());
}

// Random steps of a kernel test: a deviator of order 200 MPa, a velocity gradient of order
// 5e4 1/s split into D and W (a fixed linear congruential sequence from `seed`).
class RandomSteps {
 public:
  explicit RandomSteps(unsigned seed) : seed_(seed) {}
  std::tuple<Mat3, Mat3, Mat3> next() {
    Mat3 L, s;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) L(i, j) = 5e4 * rnd();
    s << rnd(), rnd(), rnd(), 0, rnd(), rnd(), 0, 0, rnd();
    s = 2e8 * (s + s.transpose()).eval();
    s -= s.trace() / 3.0 * Mat3::Identity();
    return {s, 0.5 * (L + L.transpose()), 0.5 * (L - L.transpose())};
  }

 private:
  double rnd() {
    seed_ = seed_ * 1664525u + 1013904223u;
    return static_cast<double>(seed_) / 4294967296.0 * 2.0 - 1.0;
  }
  unsigned seed_;
};

}  // namespace

TEST(Material, ModuliFromYoungAndPoisson) {
  const Material m = elastic(210e9, 0.3, 7850);
  EXPECT_NEAR(m.bulk_modulus, 175e9, 1e-3 * 175e9);
  EXPECT_NEAR(m.shear_modulus, 210e9 / 2.6, 1.0);
  EXPECT_NEAR(m.youngs_modulus(), 210e9, 1.0);
  EXPECT_NEAR(m.poisson_ratio(), 0.3, 1e-12);
  // c_p² = E (1-ν) / (ρ (1+ν)(1-2ν))
  EXPECT_NEAR(m.wave_speed(), std::sqrt(210e9 * 0.7 / (7850 * 1.3 * 0.4)), 1e-9);
}

TEST(Material, ElasticUniaxialStrainGivesLameStresses) {
  const Material m = elastic(70e9, 0.3, 2700);
  const double lambda = m.bulk_modulus - 2.0 / 3.0 * m.shear_modulus;
  Mat3 D = Mat3::Zero();
  D(0, 0) = 100.0;  // 1/s
  const double tau = 1e-7, e = 100.0 * tau;
  const DeviatorUpdate r = update_deviator(m, Mat3::Zero(), D, Mat3::Zero(), tau, 0.0);
  const double p = -m.bulk_modulus * e;  // linear EOS, small strain
  EXPECT_NEAR(r.s(0, 0) - p, (lambda + 2 * m.shear_modulus) * e, 1e-6);
  EXPECT_NEAR(r.s(1, 1) - p, lambda * e, 1e-6);
  EXPECT_NEAR(r.s(0, 1), 0.0, 1e-12);
  EXPECT_EQ(r.dplastic, 0.0);
}

// Uniaxial strain (compression along x) through yield, many small steps. Exact solution of
// J2 flow with linear hardening for this proportional path: σ_eq = 2G|ε| while elastic; past
// yield ε̄p = (2G|ε| − σy0) / (3G + H), σ_eq = σy0 + H ε̄p, and s_xx = −(2/3) σ_eq.
class UniaxialStrain : public ::testing::TestWithParam<double> {};

TEST_P(UniaxialStrain, RadialReturnExactAndOnYieldSurface) {
  Material m = elastic(117e9, 0.35, 8930);
  m.yield_stress = 400e6;
  m.hardening_modulus = GetParam();
  const double G = m.shear_modulus, tau = 1e-8, rate = -1e4;  // 1e-4 strain per step
  Mat3 D = Mat3::Zero();
  D(0, 0) = rate;
  Mat3 s = Mat3::Zero();
  double eps_p = 0.0;
  bool yielded = false;
  for (int n = 1; n <= 100; ++n) {
    const DeviatorUpdate r = update_deviator(m, s, D, Mat3::Zero(), tau, eps_p);
    s = r.s;
    eps_p += r.dplastic;
    const double strain = -rate * tau * n;  // |ε|
    const double elastic_eq = 2.0 * G * strain;
    if (elastic_eq <= m.yield_stress) {
      EXPECT_NEAR(von_mises(s), elastic_eq, 1e-6 * elastic_eq);
      EXPECT_EQ(eps_p, 0.0);
      continue;
    }
    yielded = true;
    const double exact_ep = (elastic_eq - m.yield_stress) / (3.0 * G + m.hardening_modulus);
    const double yield = m.yield_stress + m.hardening_modulus * exact_ep;
    EXPECT_NEAR(eps_p, exact_ep, 1e-12) << "step " << n;
    // On the yield surface, and the exact deviator of uniaxial compression.
    EXPECT_NEAR(von_mises(s), yield, 1e-9 * yield) << "step " << n;
    EXPECT_NEAR(s(0, 0), -2.0 / 3.0 * yield, 1e-9 * yield);
    EXPECT_NEAR(s(1, 1), 1.0 / 3.0 * yield, 1e-9 * yield);
    EXPECT_NEAR(s(0, 1), 0.0, 1e-9);
  }
  EXPECT_TRUE(yielded);
}

INSTANTIATE_TEST_SUITE_P(Hardening, UniaxialStrain, ::testing::Values(0.0, 100e6, 10e9),
                         [](const auto& info) {
                           return info.param == 0.0
                                      ? std::string("perfect")
                                      : "H" + std::to_string(static_cast<long>(info.param / 1e6)) +
                                            "MPa";
                         });

TEST(Material, RadialReturnFromAnyTrialLandsOnTheSurface) {
  Material m = elastic(200e9, 0.3, 7800);
  m.yield_stress = 1e9;
  m.hardening_modulus = 2e9;
  Mat3 D;
  D << 3, 1, -2, 1, -1, 0.5, -2, 0.5, 4;
  for (double scale : {1e4, 1e5, 1e6}) {
    const DeviatorUpdate r = update_deviator(m, Mat3::Zero(), scale * D, Mat3::Zero(), 1e-6, 0.05);
    ASSERT_GT(r.dplastic, 0.0);
    const double yield = m.yield_stress + m.hardening_modulus * (0.05 + r.dplastic);
    EXPECT_NEAR(von_mises(r.s), yield, 1e-12 * yield);
    EXPECT_NEAR(r.s.trace(), 0.0, 1e-3);
  }
}

TEST(Material, JaumannRotationIsOrthogonalAndKeepsPrincipalValues) {
  Mat3 W;
  W << 0, -3, 1, 3, 0, -2, -1, 2, 0;
  W *= 1e4;
  const Mat3 Q = jaumann_rotation(W, 1e-5);
  EXPECT_NEAR((Q * Q.transpose() - Mat3::Identity()).norm(), 0.0, 1e-15);
  EXPECT_NEAR(Q.determinant(), 1.0, 1e-15);
  Mat3 s;
  s << 2, 1, 0, 1, -1, 0.5, 0, 0.5, -1;
  Material m = elastic(70e9, 0.3, 2700);
  Mat3 cur = s;
  for (int n = 0; n < 10000; ++n) cur = update_deviator(m, cur, Mat3::Zero(), W, 1e-5, 0).s;
  Eigen::SelfAdjointEigenSolver<Mat3> a(s), b(cur);
  EXPECT_NEAR((a.eigenvalues() - b.eigenvalues()).norm(), 0.0, 1e-12 * s.norm());
  EXPECT_GT((cur - s).norm(), 0.1 * s.norm());  // it did rotate
}

// Mie–Grüneisen on its own Hugoniot: with E = E_H = ½ p_H μ/(1+μ) the pressure must be
// p_H = ρ0 Us up, Us = c0 + s up, at the compression μ = up / (Us − up) of the jump conditions.
TEST(Material, MieGruneisenReproducesItsHugoniot) {
  const Material m = al6061();
  for (double up : {10.0, 200.0, 500.0, 1000.0, 2000.0, 4000.0}) {
    const double us = m.c0 + m.s * up;
    const double mu = up / (us - up);
    const double p_h = m.density * us * up;
    const double e_h = 0.5 * p_h * mu / (1.0 + mu);
    EXPECT_NEAR(eos_pressure(m, mu, e_h), p_h, 1e-12 * p_h) << "up = " << up;
  }
  // The figure: about 3 GPa at up = 200 m/s for 6061-T6.
  EXPECT_NEAR(m.density * (m.c0 + m.s * 200.0) * 200.0, 2.984e9, 1e6);
  // Tension branch: linear, and energy raises the pressure by Γ0 E.
  EXPECT_NEAR(eos_pressure(m, -0.01, 0.0), -0.01 * m.bulk_modulus, 1.0);
  EXPECT_NEAR(eos_pressure(m, 0.0, 1e8), m.gamma0 * 1e8, 1e-3);
}

TEST(Material, BulkStiffnessIsTheSlopeOfTheIsentrope) {
  const Material m = al6061();
  // Integrate dE = p/(1+μ)² dμ along an isentrope and compare (1+μ) dp/dμ with bulk_stiffness.
  double e = 0.0, mu = 0.0;
  const double h = 1e-5;
  for (int k = 0; k < 5000; ++k) {
    const double p = eos_pressure(m, mu, e);
    e += h * p / ((1 + mu) * (1 + mu));
    mu += h;
  }
  const double p = eos_pressure(m, mu, e);
  const double p_next = eos_pressure(m, mu + h, e + h * p / ((1 + mu) * (1 + mu)));
  const double numeric = (1 + mu) * (p_next - p) / h;
  EXPECT_NEAR(bulk_stiffness(m, mu, p), numeric, 1e-3 * numeric);
  EXPECT_NEAR(bulk_stiffness(m, 0.0, 0.0), m.bulk_modulus, 1e-6 * m.bulk_modulus);
}

// Tillotson's terms against central differences of its pressure, in each of its regions:
// compressed, cold expanded (e ≤ E_iv), between the vaporisation energies, hot expanded
// (e ≥ E_cv), and below the reference energy (ω at e = 0).
TEST(Material, TillotsonTermsAreThePressureAndItsSlopes) {
  const Material m = al_tillotson();
  const double rho0 = m.density;
  for (const auto& [mu, e] : std::vector<std::pair<double, double>>{{0.3, 2e6},
                                                                    {0.05, 20e6},
                                                                    {-0.1, 1e6},
                                                                    {-0.3, 8e6},
                                                                    {-0.6, 5e6},
                                                                    {-0.3, 20e6},
                                                                    {-0.8, 40e6},
                                                                    {0.1, -1e5},
                                                                    {-0.2, -1e5}}) {
    const double energy = rho0 * e;  // per reference volume
    const EosTerms t = eos_terms(m, mu, energy);
    const double p = eos_pressure(m, mu, energy);
    EXPECT_DOUBLE_EQ(t.a + t.b * energy, p);
    const double hm = 1e-6, he = 1e-6 * std::max(std::abs(energy), 1e6);
    const double dp_dmu =
        (eos_pressure(m, mu + hm, energy) - eos_pressure(m, mu - hm, energy)) / (2 * hm);
    const double dp_de =
        (eos_pressure(m, mu, energy + he) - eos_pressure(m, mu, energy - he)) / (2 * he);
    EXPECT_NEAR(t.da_dmu, dp_dmu, 1e-6 * std::abs(dp_dmu) + 1e3) << mu << " " << e;
    EXPECT_NEAR(t.b, dp_de, 1e-6 * std::abs(dp_de) + 1e-9) << mu << " " << e;
  }
}

// The pressure is continuous where Tillotson's regions meet: at μ = 0 on the hot side (the
// expanded form's z = 0), and at E_iv and E_cv in expansion (the blend's ends).
TEST(Material, TillotsonIsContinuousAcrossItsRegions) {
  const Material m = al_tillotson();
  const Tillotson& t = m.tillotson;
  const double rho0 = m.density, d = 1e-9;
  for (double e : {5e6, 20e6}) {
    const double p0 = eos_pressure(m, 0.0, rho0 * e);
    EXPECT_NEAR(eos_pressure(m, -d, rho0 * e), p0, 1e-6 * p0) << e;
  }
  for (double mu : {-0.05, -0.3, -0.7})
    for (double e : {t.e_iv, t.e_cv}) {
      const double lo = eos_pressure(m, mu, rho0 * e * (1 - d));
      const double hi = eos_pressure(m, mu, rho0 * e * (1 + d));
      EXPECT_NEAR(lo, hi, 1e-6 * std::max(std::abs(lo), 1e6)) << mu << " " << e;
    }
}

// What Tillotson is for: a hot state expanded far below its reference density is a gas,
// p → a ρ e (the exponentials vanish: z = ρ0/ρ − 1 = 19 here), where Mie–Grüneisen keeps
// p = K μ + Γ0 ρ0 e whatever the density: 20 MJ/kg at a twentieth of ρ0 is 1.35 GPa there and
// 36 GPa with Mie–Grüneisen; both agree near the reference density.
TEST(Material, TillotsonExpandedHotStateIsAGas) {
  const Material til = al_tillotson(), mg = al6061();
  const double rho0 = til.density, e = 20e6, mu = 0.05 - 1.0;
  const double p = eos_pressure(til, mu, rho0 * e);
  EXPECT_NEAR(p, til.tillotson.a * (1.0 + mu) * rho0 * e, 1e-12 * p);
  EXPECT_NEAR(p, 1.35e9, 0.01e9);
  EXPECT_GT(eos_pressure(mg, mu, rho0 * e), 20 * p);
  // Near the reference state the two agree within 10 % (a shock to 10 % compression).
  const double p_til = eos_pressure(til, 0.1, rho0 * 0.2e6),
               p_mg = eos_pressure(mg, 0.1, rho0 * 0.2e6);
  EXPECT_NEAR(p_til, p_mg, 0.1 * p_mg);
}

// The material update's energy solve with Tillotson (Newton's iteration on E): each step keeps
// E^{n+1} = Eⁿ − ½ (pⁿ + p^{n+1}) ΔV exactly with the pressure it returns, that pressure lies on
// the EOS at E^{n+1}, an expansion from 20 % compression at 10 MJ/kg to three times V0 follows
// the isentrope dE/dV = −p (RK4 on 20,000 steps) to second order in the step (halving the step
// quarters the error), and the path retraced returns the start's energy to round-off.
TEST(Material, TillotsonEnergySolveKeepsTheWorkAndTheEos) {
  const Material m = al_tillotson();
  const double vol0 = 1e-9, rho0 = m.density;
  const double v_start = vol0 / 1.2, v_far = 3.0 * vol0, e_start = rho0 * vol0 * 10e6;
  const auto pressure = [&](double v, double e) {
    return eos_pressure(m, vol0 / v - 1.0, e / vol0);
  };
  // The isentrope: dE/dV = −p(V, E), RK4.
  double e_ref = e_start;
  const int n_ref = 20000;
  const double hv = (v_far - v_start) / n_ref;
  for (int k = 0; k < n_ref; ++k) {
    const double v = v_start + k * hv;
    const double k1 = -pressure(v, e_ref), k2 = -pressure(v + 0.5 * hv, e_ref + 0.5 * hv * k1);
    const double k3 = -pressure(v + 0.5 * hv, e_ref + 0.5 * hv * k2),
                 k4 = -pressure(v + hv, e_ref + hv * k3);
    e_ref += hv * (k1 + 2 * k2 + 2 * k3 + k4) / 6.0;
  }
  double worst_eos = 0.0;
  // Out to v_far in `steps` steps (the error against the isentrope there), and back.
  const auto loop = [&](int steps, double& far_error) {
    double vol = v_start, e = e_start, p = pressure(v_start, e_start);
    for (int dir = 0; dir < 2; ++dir)
      for (int k = 0; k < steps; ++k) {
        const double f = double(k + 1) / steps;
        const double v_next =
            dir == 0 ? v_start + (v_far - v_start) * f : v_far - (v_far - v_start) * f;
        const double dvol = v_next - vol, mu = vol0 / v_next - 1.0;
        const EnergySolve s = solve_energy(m, mu, e, 0.0, p, dvol, vol0);
        EXPECT_NEAR(s.e, e - 0.5 * (p + s.p) * dvol, 1e-12 * std::abs(e));
        worst_eos = std::max(worst_eos, std::abs(s.p - eos_pressure(m, mu, s.e / vol0)) /
                                            std::max(std::abs(s.p), 1e8));
        e = s.e, p = s.p, vol = v_next;
        if (dir == 0 && k + 1 == steps) far_error = std::abs(e / e_ref - 1.0);
      }
    return std::abs(e / e_start - 1.0);
  };
  double coarse = 0.0, fine = 0.0;
  const double back_coarse = loop(50, coarse), back_fine = loop(100, fine);
  std::printf(
      "Tillotson expansion: energy off the isentrope %.3e (50 steps), %.3e (100); back "
      "at the start %.1e, %.1e; pressure off its EOS by %.2e\n",
      coarse, fine, back_coarse, back_fine, worst_eos);
  EXPECT_LT(worst_eos, 1e-9);
  EXPECT_LT(fine, 1e-3);
  EXPECT_NEAR(coarse / fine, 4.0, 0.5);
  EXPECT_LT(back_coarse, 1e-12);
  EXPECT_LT(back_fine, 1e-12);
}

TEST(Material, TillotsonBulkStiffnessIsTheSlopeOfTheIsentrope) {
  const Material m = al_tillotson();
  const double rho0 = m.density;
  for (const auto& [mu0, e0] :
       std::vector<std::pair<double, double>>{{0.2, 1e6}, {-0.3, 8e6}, {-0.5, 20e6}}) {
    double e = rho0 * e0;
    const double h = 1e-6;
    const double p = eos_pressure(m, mu0, e);
    const double p_next = eos_pressure(m, mu0 + h, e + h * p / ((1 + mu0) * (1 + mu0)));
    const double p_prev = eos_pressure(m, mu0 - h, e - h * p / ((1 + mu0) * (1 + mu0)));
    const double numeric = (1 + mu0) * (p_next - p_prev) / (2 * h);
    EXPECT_NEAR(bulk_stiffness(m, mu0, p, e), numeric, 1e-4 * numeric) << mu0 << " " << e0;
  }
}

TEST(Material, ViscosityOnlyInCompression) {
  EXPECT_EQ(bulk_viscosity(2700, 1e-3, 5000, +1e5, 0.06, 1.5), 0.0);
  EXPECT_EQ(bulk_viscosity(2700, 1e-3, 5000, 0.0, 0.06, 1.5), 0.0);
  const double q = bulk_viscosity(2700, 1e-3, 5000, -1e5, 0.06, 1.5);
  // ρ l (C2 l ε̇² + C1 c |ε̇|) = 2700e-3 (1.5e-3·1e10 + 0.06·5000·1e5) = 2700e-3 · 4.5e7
  EXPECT_NEAR(q, 2700 * 1e-3 * (1.5 * 1e-3 * 1e10 + 0.06 * 5000 * 1e5), 1e-3);
}

// The kernel's symmetric fast path equals the Mat3 reference, elastic and plastic, with spin.
TEST(Material, FastDeviatorMatchesReference) {
  Material m = elastic(117e9, 0.35, 8930);
  m.yield_stress = 400e6;
  m.hardening_modulus = 100e6;
  RandomSteps steps(12345);
  for (int k = 0; k < 200; ++k) {
    const auto [s, D, W] = steps.next();
    const double tau = 1e-7, eps = 0.01 * (k % 3);
    const DeviatorUpdate ref = update_deviator(m, s, D, W, tau, eps);
    Sym6 fast = to_sym6(s);
    const DeviatorIncrement r =
        update_deviator6(m, fast, to_sym6(D), {W(2, 1), W(0, 2), W(1, 0)}, tau, eps);
    EXPECT_NEAR((to_mat3(fast) - ref.s).norm(), 0.0, 1e-12 * ref.s.norm()) << k;
    EXPECT_NEAR(r.dplastic, ref.dplastic, 1e-15) << k;
  }
}

// Johnson–Cook against closed forms. A pure shear rate γ̇ (D12 = D21 = γ̇/2) held
// until the stress is steady: the von Mises rate is ε̇ = γ̇/√3, and once steady all of it is
// plastic.
namespace {

Material johnson_cook(double a, double b, double n, double c, double m_exp, double melt) {
  Material m = al6061();
  m.strength = StrengthModel::johnson_cook;
  m.yield_stress = 0.0;
  m.johnson_cook = {a, b, n, c, 1.0, m_exp, 293.0, melt};
  return m;
}

// Runs `steps` steps of shear at rate `gamma_dot` from zero stress; returns the final stress,
// the plastic strain and the temperature (heated as the element kernel heats a tet).
struct Sheared {
  Mat3 s;
  double eps = 0.0, temperature = 0.0;
};
// pressure and eta: a held pressure and compression ρ/ρ0 (Steinberg–Guinan).
Sheared shear(const Material& m, double gamma_dot, double tau, int steps, double pressure = 0.0,
              double eta = 1.0) {
  Mat3 D = Mat3::Zero();
  D(0, 1) = D(1, 0) = 0.5 * gamma_dot;
  Sheared out{Mat3::Zero(), 0.0, m.start_temperature()};
  for (int k = 0; k < steps; ++k) {
    const DeviatorUpdate r = update_deviator(m, out.s, D, Mat3::Zero(), tau, out.eps,
                                             out.temperature, eta * m.density, pressure);
    out.s = r.s;
    out.eps += r.dplastic;
    if (m.thermal())
      out.temperature += m.taylor_quinney * r.yield * r.dplastic / (m.density * m.specific_heat);
  }
  return out;
}

// A law that reduces to the bilinear one, against its closed form over random steps: `perfect`
// to perfect plasticity at σy0 = 0.29 GPa (to 1e-14), `linear` to linear hardening H (1e-12),
// each called at the temperature and pressure given.
void expect_bilinear(const Material& perfect, const Material& linear, double hardening,
                     double temperature, double pressure, unsigned seed) {
  Material bilinear = al6061();
  RandomSteps steps(seed);
  for (int k = 0; k < 200; ++k) {
    const auto [s, D, W] = steps.next();
    const double tau = 1e-7, eps = 0.01 * (k % 3);
    bilinear.hardening_modulus = 0.0;
    const DeviatorUpdate a = update_deviator(bilinear, s, D, W, tau, eps);
    const DeviatorUpdate b =
        update_deviator(perfect, s, D, W, tau, eps, temperature, 2703.0, pressure);
    EXPECT_NEAR(a.dplastic, b.dplastic, 1e-14 * a.dplastic) << k;
    EXPECT_NEAR((a.s - b.s).norm(), 0.0, 1e-14 * a.s.norm()) << k;
    bilinear.hardening_modulus = hardening;
    const DeviatorUpdate c = update_deviator(bilinear, s, D, W, tau, eps);
    const DeviatorUpdate d =
        update_deviator(linear, s, D, W, tau, eps, temperature, 2703.0, pressure);
    EXPECT_NEAR(c.dplastic, d.dplastic, 1e-12 * c.dplastic + 1e-300) << k;
    EXPECT_NEAR((c.s - d.s).norm(), 0.0, 1e-12 * c.s.norm()) << k;
    if (d.dplastic > 0.0) {
      EXPECT_NEAR(von_mises(d.s), d.yield, 1e-12 * d.yield) << k;
    }
  }
}

}  // namespace

// B = 0, C = 0, no temperature: perfectly plastic at A, the bilinear law with H = 0; n = 1:
// linear hardening H = B; both to round-off (the return solves for Δε̄p, which the bilinear law
// has in closed form).
TEST(Material, JohnsonCookReducesToTheBilinearLaw) {
  expect_bilinear(johnson_cook(0.29e9, 0.0, 1.0, 0.0, 1.0, 0.0),
                  johnson_cook(0.29e9, 1.2e9, 1.0, 0.0, 1.0, 0.0), 1.2e9, 293.0, 0.0, 777);
}

// Rate: perfectly plastic (B = 0) sheared at a steady rate flows at
// σ = A (1 + C ln(ε̇/ε̇0)), the yield at the step's own plastic rate (not lagged).
TEST(Material, JohnsonCookSteadyFlowStressAtTheStrainRate) {
  const double a = 0.3e9, c = 0.015;
  const Material m = johnson_cook(a, 0.0, 1.0, c, 1.0, 0.0);
  for (const double gamma_dot : {1e3, 1e5}) {
    const double tau = 2e-3 / gamma_dot;  // 1,000 steps to a shear of 2
    const Sheared r = shear(m, gamma_dot, tau, 1000);
    const double rate = gamma_dot / std::sqrt(3.0);
    EXPECT_NEAR(von_mises(r.s), a * (1.0 + c * std::log(rate)), 1e-9 * a) << gamma_dot;
  }
  // Below the reference rate: no softening (ε̇* clamped at 1).
  const Sheared slow = shear(m, 0.5, 2e-3 / 0.5, 1000);
  EXPECT_NEAR(von_mises(slow.s), a, 1e-9 * a);
}

// Temperature held (no specific heat): σ = A (1 − T*ᵐ); at or above melt, no deviator.
TEST(Material, JohnsonCookThermalSofteningAndMelt) {
  Material m = johnson_cook(0.3e9, 0.0, 1.0, 0.0, 1.34, 925.0);
  m.initial_temperature = 600.0;
  const Sheared warm = shear(m, 1e3, 1e-6, 2000);
  const double ts = (600.0 - 293.0) / (925.0 - 293.0);
  EXPECT_NEAR(von_mises(warm.s), 0.3e9 * (1.0 - std::pow(ts, 1.34)), 1e-6);
  m.initial_temperature = 925.0;
  const Sheared molten = shear(m, 1e3, 1e-6, 10);
  EXPECT_EQ(von_mises(molten.s), 0.0);
}

// Adiabatic heating, m = 1, B = C = 0: dσ/dε̄p = −A χ σ / ((T_m − T_r) ρ c_v), so
// σ = A exp(−k ε̄p) with k = A χ / ((T_m − T_r) ρ c_v). The return heats within the step
// (implicit), which converges to the exponential as the steps shrink.
TEST(Material, JohnsonCookAdiabaticSofteningFollowsTheExponential) {
  Material m = johnson_cook(0.3e9, 0.0, 1.0, 0.0, 1.0, 925.0);
  m.specific_heat = 896.0;
  m.taylor_quinney = 0.9;
  const double k = 0.3e9 * 0.9 / ((925.0 - 293.0) * m.density * 896.0);
  const Sheared r = shear(m, 1e3, 1e-6, 2000);  // a shear of 2: ε̄p ≈ 1.15
  EXPECT_GT(r.eps, 1.0);
  EXPECT_NEAR(von_mises(r.s) / (0.3e9 * std::exp(-k * r.eps)), 1.0, 2e-3);
  // The heat is χ times the plastic work: T − T_r = χ ∫σ dε̄p / (ρ c_v) = (A − σ)/(A k)·…
  const double t_expected = 293.0 + (925.0 - 293.0) * (1.0 - std::exp(-k * r.eps));
  EXPECT_NEAR(r.temperature, t_expected, 0.5);
}

// Steinberg–Guinan against closed forms.
namespace {

// Al 6061-T6's [S96] set (data/materials.yaml), with the terms a test switches off.
Material steinberg(double beta, double n, double ymax, double a_p, double b_t, double melt) {
  Material m = al6061();
  m.strength = StrengthModel::steinberg_guinan;
  m.yield_stress = 0.0;
  SteinbergGuinan& sg = m.steinberg_guinan;
  sg.y0 = 0.29e9;
  sg.ymax = ymax;
  sg.beta = beta;
  sg.n = n;
  sg.a_pressure = a_p;
  sg.b_temperature = b_t;
  sg.melt_temperature = melt;
  sg.gamma0 = 1.97;
  sg.a = 1.5;
  return m;
}

}  // namespace

// No pressure or temperature terms: β = 0 is perfect plasticity at Y0, n = 1 the linear
// hardening H = Y0 β, both to round-off against the bilinear law's closed form.
TEST(Material, SteinbergGuinanReducesToTheBilinearLaw) {
  expect_bilinear(steinberg(0.0, 1.0, 0.0, 0.0, 0.0, 0.0), steinberg(4.0, 1.0, 0.0, 0.0, 0.0, 0.0),
                  4.0 * 0.29e9, 300.0, 1e9, 4242);
}

// Work hardening Y0 [1 + β ε̄p]ⁿ, on the surface at every step, capped at Ymax.
TEST(Material, SteinbergGuinanHardeningCurveAndCap) {
  const double beta = 125.0, n = 0.1, ymax = 0.68e9;
  const Material m = steinberg(beta, n, ymax, 0.0, 0.0, 0.0);
  // A shear of 0.01 (ε̄p ≈ 0.004): below the cap, Y0 (1 + 125 · 0.004)^0.1 ≈ 0.302 GPa.
  const Sheared early = shear(m, 1e4, 1e-8, 100);
  ASSERT_GT(early.eps, 1e-3);
  EXPECT_NEAR(von_mises(early.s), 0.29e9 * std::pow(1.0 + beta * early.eps, n), 1e-12 * 0.29e9);
  // The cap: Y0 (1 + β ε̄p)^0.1 = Ymax at ε̄p = ((Ymax/Y0)^10 − 1)/β ≈ 40: with n = 0.5 it is
  // reached at ε̄p = 0.04.
  const Material fast = steinberg(beta, 0.5, ymax, 0.0, 0.0, 0.0);
  const Sheared late = shear(fast, 1e4, 1e-8, 2000);  // a shear of 0.2
  ASSERT_GT(late.eps, (std::pow(ymax / 0.29e9, 2.0) - 1.0) / beta);
  EXPECT_NEAR(von_mises(late.s), ymax, 1e-12 * ymax);
}

// Pressure and temperature scale G and Y by 1 + A P η^(−1/3) − B (T − 300): the elastic
// shear stress of a small shear is 2 G(P, T) τ D12, the flow stress Y0 times the same factor;
// a tensile pressure leaves G0.
TEST(Material, SteinbergGuinanPressureAndTemperatureScaleModulusAndYield) {
  const double a_p = 6.52e-11, b_t = 6.16e-4;
  Material m = steinberg(0.0, 1.0, 0.0, a_p, b_t, 0.0);
  m.initial_temperature = 500.0;
  const double p = 5e9, eta = 1.05;
  const double factor = 1.0 + a_p * p / std::cbrt(eta) - b_t * (500.0 - 300.0);
  const Sheared elastic = shear(m, 1e3, 1e-8, 1, p, eta);
  EXPECT_NEAR(elastic.s(0, 1), 27.6e9 * factor * 1e3 * 1e-8, 1e-12 * 27.6e9 * 1e-5);
  const Sheared flowing = shear(m, 1e4, 1e-7, 2000, p, eta);
  EXPECT_NEAR(von_mises(flowing.s), 0.29e9 * factor, 1e-9 * 0.29e9);
  const Sheared tension = shear(m, 1e3, 1e-8, 1, -5e9, 0.95);
  EXPECT_NEAR(tension.s(0, 1), 27.6e9 * (1.0 - b_t * 200.0) * 1e-5, 1e-12 * 27.6e9 * 1e-5);
}

// The melt law: T_m(1) = T_m0, and Lindemann's d ln T_m / d ln ρ = 2 (Γ0 − 1/3) at η = 1; at
// or above T_m(η) no deviator, just below it the (softened) yield.
TEST(Material, SteinbergGuinanMeltsByTheLindemannLaw) {
  const Material m = steinberg(0.0, 1.0, 0.0, 6.52e-11, 6.16e-4, 1220.0);
  const SteinbergGuinan& sg = m.steinberg_guinan;
  EXPECT_DOUBLE_EQ(steinberg_melt_temperature(sg, 1.0), 1220.0);
  const double h = 1e-6;
  const double slope = (std::log(steinberg_melt_temperature(sg, 1.0 + h)) -
                        std::log(steinberg_melt_temperature(sg, 1.0 - h))) /
                       (std::log(1.0 + h) - std::log(1.0 - h));
  EXPECT_NEAR(slope, 2.0 * (1.97 - 1.0 / 3.0), 1e-8);
  // η = 1.2 with its pressure on aluminium's Hugoniot (about 20 GPa): the pressure term keeps
  // G above zero up to the raised melt point.
  const double eta = 1.2, p = 20e9, tm = steinberg_melt_temperature(sg, eta);
  EXPECT_GT(tm, 1220.0);  // compression raises the melt point
  Material hot = m;
  hot.initial_temperature = tm * (1.0 + 1e-12);
  EXPECT_EQ(von_mises(shear(hot, 1e3, 1e-6, 10, p, eta).s), 0.0);
  hot.initial_temperature = tm * (1.0 - 1e-6);
  const double factor =
      1.0 + 6.52e-11 * p / std::cbrt(eta) - 6.16e-4 * (hot.initial_temperature - 300.0);
  ASSERT_GT(factor, 0.0);
  EXPECT_NEAR(von_mises(shear(hot, 1e4, 1e-7, 2000, p, eta).s), 0.29e9 * factor, 1e-9 * 0.29e9);
}

// The return's two shortcuts change no answer. The melt point's lower bound (no exp, no pow)
// lies below T_m(η) at every compression and meets it at η = 1; an elastic step is decided
// against min(Y0, Ymax) G/G0 before the hardening is computed. Oracle: the elastic/plastic
// decision from the full yield σy(0) = Y(ε̄p) G(P, T)/G0 over trial stresses on both sides of
// the bound and of σy(0), and the melt just above and below T_m(η).
TEST(Material, SteinbergGuinanShortcutsAgreeWithTheFullComputation) {
  const Material m = steinberg(125.0, 0.1, 0.68e9, 6.52e-11, 6.16e-4, 1220.0);
  const SteinbergGuinan& sg = m.steinberg_guinan;
  for (double eta = 0.5; eta <= 2.0; eta += 0.01)
    EXPECT_LE(steinberg_melt_lower_bound(sg, eta), steinberg_melt_temperature(sg, eta)) << eta;
  EXPECT_NEAR(steinberg_melt_lower_bound(sg, 1.0), 1220.0, 1e-8 * 1220.0);

  const double eps = 0.05, temperature = 400.0, p = 2e9, eta = 1.02, rho = eta * m.density;
  const StrengthState ss = strength_state(m, p, temperature, eta);
  double slope = 0.0;
  const double y_full =
      steinberg_hardening(sg, eps, slope) *
      (ss.pressure_factor - sg.b_temperature * (temperature - sg.reference_temperature));
  const double bound = sg.y0 * y_full / steinberg_hardening(sg, eps, slope);
  ASSERT_LT(bound, 0.85 * y_full);  // trial stresses between the two: elastic by the full yield
  for (double f = 0.5; f <= 1.5; f += 0.01) {
    const double eq = f * y_full;
    const PlasticIncrement r = plastic_increment(m, eq, eps, 1e-8, temperature, rho, p);
    EXPECT_EQ(r.dplastic > 0.0, eq > y_full) << f;
    if (r.dplastic > 0.0) {
      // The return: on the trial stress's radial line, eq − 3G Δε̄p, and between the yield it
      // started from and the trial stress (the law hardens with ε̄p).
      EXPECT_NEAR(r.yield, eq - 3.0 * ss.g * r.dplastic, 1e-12 * eq) << f;
      EXPECT_GE(r.yield, y_full * (1.0 - 1e-12)) << f;
      EXPECT_LE(r.yield, eq) << f;
    } else {
      EXPECT_GE(r.yield, eq) << f;  // an elastic step scales nothing
    }
  }
  // Molten above T_m(η), not just below it, whether or not the bound decided.
  for (double e : {0.97, 1.0, 1.1}) {
    const double tm = steinberg_melt_temperature(sg, e);
    EXPECT_EQ(strength_state(m, p, tm * (1.0 + 1e-12), e).g, 0.0) << e;
    EXPECT_GT(strength_state(m, p, tm * (1.0 - 1e-9), e).g, 0.0) << e;
    EXPECT_GT(strength_state(m, p, 300.0, e).g, 0.0) << e;
  }
}

// The return's Newton solve ends at round-off, by whichever rule stops it (a step at
// round-off, the quadratic convergence its steps show, a narrowed bracket): over trial stresses
// from just above yield to five times it, plastic strains, steps and temperatures up to melt,
// the returned yield eq − 3G Δε̄p is the law's yield at ε̄p + Δε̄p (its rate Δε̄p/τ and the
// step's heating T + χ σy Δε̄p / (ρ c_v)), evaluated apart by johnson_cook_yield and
// steinberg_hardening, to 1e-12 of the trial stress.
TEST(Material, ReturnsLandOnTheLawsYieldToRoundOff) {
  Material jc = johnson_cook(324e6, 114e6, 0.42, 0.002, 1.34, 925.0);
  Material sg = steinberg(125.0, 0.1, 0.68e9, 6.52e-11, 6.16e-4, 1220.0);
  for (Material* m : {&jc, &sg}) m->specific_heat = 896.0, m->taylor_quinney = 0.9;
  const double g3 = 3.0 * jc.shear_modulus;
  int plastic = 0;
  for (const double eps : {0.0, 1e-4, 0.05, 0.5, 2.0})
    for (const double tau : {1e-10, 1e-8, 1e-6})
      for (const double temperature : {293.0, 600.0, 900.0})
        for (double f = 1.001; f < 5.0; f *= 1.07) {
          const double rho = jc.density;
          // Johnson–Cook: σy(Δ) = S(ε̄p + Δ) R(Δ/τ) Θ(T(Δ)).
          const double yj = johnson_cook_yield(jc.johnson_cook, eps, 0.0, temperature);
          const double eq = f * yj;
          const PlasticIncrement a = plastic_increment(jc, eq, eps, tau, temperature, rho);
          ASSERT_GT(a.dplastic, 0.0);
          const double heat = 0.9 / (rho * 896.0);
          const double tj = temperature + heat * a.yield * a.dplastic;
          EXPECT_NEAR(a.yield,
                      johnson_cook_yield(jc.johnson_cook, eps + a.dplastic, a.dplastic / tau, tj),
                      1e-12 * eq)
              << eps << " " << tau << " " << temperature << " " << f;
          EXPECT_NEAR(a.yield, eq - g3 * a.dplastic, 1e-15 * eq);
          // Steinberg–Guinan at 2 GPa: σy(Δ) = Y(ε̄p + Δ) [c_p − B (T(Δ) − T_ref)].
          const double p = 2e9, eta = 1.02;
          const StrengthState ss = strength_state(sg, p, temperature, eta);
          double slope = 0.0;
          const auto y_sg = [&](double e, double t) {
            const double factor =
                ss.pressure_factor -
                sg.steinberg_guinan.b_temperature * (t - sg.steinberg_guinan.reference_temperature);
            return steinberg_hardening(sg.steinberg_guinan, e, slope) * factor;
          };
          const double eq_sg = f * y_sg(eps, temperature);
          const PlasticIncrement b =
              plastic_increment(sg, eq_sg, eps, tau, temperature, eta * sg.density, p);
          ASSERT_GT(b.dplastic, 0.0);
          const double ts = temperature + 0.9 / (eta * sg.density * 896.0) * b.yield * b.dplastic;
          ASSERT_LT(ts, steinberg_melt_temperature(sg.steinberg_guinan, eta));
          EXPECT_NEAR(b.yield, y_sg(eps + b.dplastic, ts), 1e-12 * eq_sg)
              << eps << " " << tau << " " << temperature << " " << f;
          plastic += 2;
        }
  EXPECT_EQ(plastic, 2 * 5 * 3 * 3 * 24);
}

// Johnson–Cook's return calls a step elastic exactly where the law's own σy(0) (its pows, by
// johnson_cook_yield) is not exceeded, whatever its cheap lower bound of σy(0) decides: below
// room temperature, up to half-way to melt (m ≥ 1: the bound A (1 − T*)), beyond (no bound),
// with m < 1 (no bound above room temperature), at trial stresses a part in 1e9 either side of
// σy(0) and far below it.
TEST(Material, JohnsonCookElasticStepsAreThoseBelowTheLawsYield) {
  int elastic = 0, plastic = 0;
  for (const double m_exp : {1.34, 1.0, 0.8})
    for (const double temperature : {200.0, 293.0, 400.0, 609.0, 610.0, 800.0}) {
      Material jc = johnson_cook(324e6, 114e6, 0.42, 0.002, m_exp, 925.0);
      jc.specific_heat = 896.0;
      for (const double eps : {0.0, 1e-3, 0.5})
        for (const double f : {0.3, 0.9, 1.0 - 1e-9, 1.0 + 1e-9, 1.5}) {
          const double y0 = johnson_cook_yield(jc.johnson_cook, eps, 0.0, temperature);
          const double eq = f * y0;
          const PlasticIncrement r = plastic_increment(jc, eq, eps, 1e-8, temperature, jc.density);
          const bool yields = eq > y0;
          EXPECT_EQ(r.dplastic > 0.0, yields)
              << "m " << m_exp << " T " << temperature << " eps " << eps << " f " << f;
          if (!yields) {
            EXPECT_GE(r.yield, eq);  // nothing is scaled
          }
          (yields ? plastic : elastic) += 1;
        }
    }
  EXPECT_EQ(elastic, 3 * 6 * 3 * 3);
  EXPECT_EQ(plastic, 3 * 6 * 3 * 2);
}

// Adiabatic heating, β = 0: dY/dε̄p = −Y0 B χ Y / (ρ c_v), so Y = Y0 exp(−k ε̄p) with
// k = Y0 B χ / (ρ c_v) (the heat is solved within each step's return).
TEST(Material, SteinbergGuinanAdiabaticSofteningFollowsTheExponential) {
  Material m = steinberg(0.0, 1.0, 0.0, 0.0, 6.16e-4, 0.0);
  m.specific_heat = 885.0;
  m.taylor_quinney = 0.9;
  const double k = 0.29e9 * 6.16e-4 * 0.9 / (m.density * 885.0);
  const Sheared r = shear(m, 1e3, 1e-6, 2000);
  EXPECT_GT(r.eps, 1.0);
  EXPECT_NEAR(von_mises(r.s) / (0.29e9 * std::exp(-k * r.eps)), 1.0, 2e-3);
  EXPECT_NEAR(r.temperature, 300.0 + (1.0 - std::exp(-k * r.eps)) / 6.16e-4, 0.5);
}

// The metal's cold work ε̄p0 (`initial_plastic_strain`) is where each law's hardening starts: the
// return from ε̄p is the return of the same metal without it from ε̄p0 + ε̄p, to the last bit, and
// Steinberg–Guinan's first yield is Y0 [1 + β (εi + ε̄p0)]ⁿ.
TEST(Material, InitialPlasticStrainIsWhereTheHardeningStarts) {
  Material bilinear = al6061();
  bilinear.hardening_modulus = 0.5e9;
  Material jc = al6061();
  jc.strength = StrengthModel::johnson_cook;
  jc.yield_stress = 0.0;
  jc.johnson_cook.a = 324e6;
  jc.johnson_cook.b = 114e6;
  jc.johnson_cook.n = 0.42;
  jc.johnson_cook.c = 0.002;
  jc.johnson_cook.m = 1.34;
  jc.johnson_cook.melt_temperature = 925.0;
  jc.specific_heat = 885.0;
  const Material sg = steinberg(125.0, 0.1, 0.68e9, 6.52e-11, 6.16e-4, 1220.0);
  for (const Material& plain : {bilinear, jc, sg}) {
    Material worked = plain;
    worked.initial_plastic_strain = 0.2;
    for (double eq = 0.2e9; eq <= 0.8e9; eq += 0.05e9) {
      const PlasticIncrement a = plastic_increment(worked, eq, 0.03, 1e-8, 400.0, 2750.0, 1e9);
      const PlasticIncrement b = plastic_increment(plain, eq, 0.23, 1e-8, 400.0, 2750.0, 1e9);
      EXPECT_EQ(a.dplastic, b.dplastic) << plain.name << " " << eq;
      EXPECT_EQ(a.yield, b.yield) << plain.name << " " << eq;
    }
  }
  // The work-hardened metal yields higher: Y0 (1 + 125 · 0.2)^0.1 = 0.4017 GPa against 0.29 GPa
  // (no pressure, 300 K: G/G0 = 1); a trial stress 0.1 % above it returns to it (the step's own
  // hardening is 1e-5 of it), 1 % below it is elastic.
  Material worked = steinberg(125.0, 0.1, 0.68e9, 0.0, 0.0, 0.0);
  worked.initial_plastic_strain = 0.2;
  const double y = 0.29e9 * std::pow(1.0 + 125.0 * 0.2, 0.1);
  EXPECT_NEAR(plastic_increment(worked, 1.001 * y, 0.0, 1e-8, 300.0, worked.density).yield, y,
              1e-4 * y);
  EXPECT_EQ(plastic_increment(worked, 0.99 * y, 0.0, 1e-8, 300.0, worked.density).dplastic, 0.0);
}

// Johnson–Cook's failure strain against its closed form, with 4340 steel's [JC85]
// constants: ε_f = [D1 + D2 exp(D3 σ*)] [1 + D4 ln ε̇*] [1 + D5 T*]; no rate term below the
// reference rate, T* clamped to [0, 1], and the floor where D1 < 0 makes it negative.
TEST(Material, JohnsonCookFailureStrainIsItsClosedForm) {
  JohnsonCookFailure f;
  f.d1 = 0.05, f.d2 = 3.44, f.d3 = -2.12, f.d4 = 0.002, f.d5 = 0.61;
  f.room_temperature = 293.0, f.melt_temperature = 1793.0;
  // Uniaxial tension (σ* = 1/3) at the reference rate and room temperature.
  const double uniaxial = 0.05 + 3.44 * std::exp(-2.12 / 3.0);
  EXPECT_NEAR(johnson_cook_failure_strain(f, 1.0 / 3.0, 1.0, 293.0), uniaxial, 1e-15);
  EXPECT_NEAR(uniaxial, 1.7469, 1e-4);  // the number by hand
  // Higher triaxiality fails sooner (D3 < 0); compression later.
  EXPECT_LT(johnson_cook_failure_strain(f, 1.0, 1.0, 293.0), uniaxial);
  EXPECT_GT(johnson_cook_failure_strain(f, -0.3, 1.0, 293.0), uniaxial);
  // Rate: 1 + D4 ln(ε̇/ε̇0) above the reference rate, none below it.
  EXPECT_NEAR(johnson_cook_failure_strain(f, 1.0 / 3.0, 1e4, 293.0),
              uniaxial * (1.0 + 0.002 * std::log(1e4)), 1e-14);
  EXPECT_EQ(johnson_cook_failure_strain(f, 1.0 / 3.0, 1e-3, 293.0), uniaxial);
  // Temperature: 1 + D5 T*, T* = 0.5 halfway to melt, clamped at melt and below room.
  EXPECT_NEAR(johnson_cook_failure_strain(f, 1.0 / 3.0, 1.0, 1043.0), uniaxial * 1.305, 1e-14);
  EXPECT_NEAR(johnson_cook_failure_strain(f, 1.0 / 3.0, 1.0, 5000.0), uniaxial * 1.61, 1e-14);
  EXPECT_EQ(johnson_cook_failure_strain(f, 1.0 / 3.0, 1.0, 100.0), uniaxial);
  // 6061-T6 [L01]: D1 = −0.77 makes ε_f negative above σ* ≈ 1.35: floored at min_strain.
  JohnsonCookFailure al;
  al.d1 = -0.77, al.d2 = 1.45, al.d3 = -0.47;
  EXPECT_NEAR(johnson_cook_failure_strain(al, 0.0, 1.0, 293.0), 0.68, 1e-15);
  EXPECT_EQ(johnson_cook_failure_strain(al, 2.0, 1.0, 293.0), al.min_strain);
}
