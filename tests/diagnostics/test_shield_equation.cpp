// Christiansen's Whipple-shield equation against the published equations written here again
// in their own units (cm, g/cm³, km/s, ksi; the module's code is not read), and the case file's
// `shield_equation:` and `mesh_study:` as the shipped Whipple case declares them.
//
//   E. L. Christiansen, Int. J. Impact Eng. 14 (1993) 145–156; NASA TP-2003-210788.
#include <gtest/gtest.h>

#include <cmath>

#include "../test_util.hpp"
#include "tetcontact/diagnostics/shield_equation.hpp"
#include "tetcontact/io/case.hpp"

namespace {

// The published equations: d_c in cm.
double published(double V, double tb, double tw, double S, double rp, double rb, double sigma,
                 double theta_deg) {
  const double c = std::cos(theta_deg * M_PI / 180.0), Vn = V * c;
  if (Vn <= 3.0)
    return std::pow((tw * std::pow(sigma / 40.0, 0.5) + tb) /
                        (0.6 * std::pow(c, 5.0 / 3.0) * std::pow(rp, 0.5) * std::pow(V, 2.0 / 3.0)),
                    18.0 / 19.0);
  const double high = std::pow(tw, 2.0 / 3.0) * std::pow(rp, -1.0 / 3.0) *
                      std::pow(rb, -1.0 / 9.0) * std::pow(S, 1.0 / 3.0) *
                      std::pow(sigma / 70.0, 1.0 / 3.0);
  if (Vn >= 7.0) return 3.918 * high * std::pow(Vn, -2.0 / 3.0);
  const double low = std::pow(
      (tw * std::pow(sigma / 40.0, 0.5) + tb) / (1.248 * std::pow(rp, 0.5) * c), 18.0 / 19.0);
  return low * (1.75 - Vn / 4.0) + 1.071 * high * (Vn / 4.0 - 0.75);
}

constexpr double k_ksi = 6.894757293168e6;

// A shot in SI from the equation's units.
tc::WhippleShot shot(double V, double tb, double tw, double S, double rp, double rb, double sigma,
                     double theta_deg, double d_cm = 0.3) {
  tc::WhippleShot s;
  s.diameter = d_cm / 100.0;
  s.speed = V * 1000.0;
  s.obliquity_deg = theta_deg;
  s.bumper_thickness = tb / 100.0;
  s.standoff = S / 100.0;
  s.wall_thickness = tw / 100.0;
  s.wall_yield = sigma * k_ksi;
  s.projectile_density = rp * 1000.0;
  s.bumper_density = rb * 1000.0;
  return s;
}

}  // namespace

TEST(ShieldEquation, MatchesThePublishedEquationsInEachRegime) {
  struct Shield {
    double tb, tw, S, rb, sigma;
  };
  // whipple.yaml's default (1 mm, 2 mm, 30 mm, 6061-T6's 40 ksi), a thicker shield with a
  // stronger wall, and one with a denser bumper.
  const Shield shields[] = {
      {0.1, 0.2, 3.0, 2.7, 40.0}, {0.127, 0.318, 10.0, 2.7, 70.0}, {0.08, 0.16, 5.0, 2.85, 55.0}};
  int checked = 0;
  for (const Shield& sh : shields)
    for (const double V : {0.5, 1.0, 2.0, 2.9, 3.2, 4.0, 5.0, 6.0, 6.8, 7.2, 8.0, 10.0, 15.0})
      for (const double theta : {0.0, 30.0, 45.0}) {
        const tc::WhippleShot s = shot(V, sh.tb, sh.tw, sh.S, 2.7, sh.rb, sh.sigma, theta);
        const double want = published(V, sh.tb, sh.tw, sh.S, 2.7, sh.rb, sh.sigma, theta);
        EXPECT_NEAR(tc::christiansen_critical_diameter(s) * 100.0, want, 1e-12 * want)
            << "V " << V << " theta " << theta;
        const double Vn = V * std::cos(theta * M_PI / 180.0);
        const tc::ShieldRegime r = tc::christiansen_regime(s);
        EXPECT_EQ(r, Vn <= 3.0   ? tc::ShieldRegime::ballistic
                     : Vn >= 7.0 ? tc::ShieldRegime::hypervelocity
                                 : tc::ShieldRegime::shatter);
        ++checked;
      }
  EXPECT_EQ(checked, 3 * 13 * 3);
}

// The shatter line meets the two regimes at its ends: the critical diameter is continuous at
// V cos θ = 3 and 7 km/s (a check of 1.248 = 0.6 · 3^(2/3) and 1.071 = 3.918 · 7^(−2/3), as
// published to four figures: 1.071 is 3e-4 above 3.918 · 7^(−2/3), 1.248 4e-5 below 0.6 · 3^(2/3)).
TEST(ShieldEquation, IsContinuousAtTheRegimesEdges) {
  for (const double edge : {3.0, 7.0}) {
    const double below = tc::christiansen_critical_diameter(
                     shot(edge - 1e-9, 0.1, 0.2, 3.0, 2.7, 2.7, 40.0, 0.0)),
                 above = tc::christiansen_critical_diameter(
                     shot(edge + 1e-9, 0.1, 0.2, 3.0, 2.7, 2.7, 40.0, 0.0));
    EXPECT_NEAR(below, above, 5e-4 * below) << edge << " km/s";
  }
}

// The figures a user met (the default shield, ρ 2.7, σ 40 ksi): 1.62 mm at 3 km/s and 2.67 mm
// at 6.5 km/s, normal; 2.18 mm at 5 km/s and 30°, where a 3.0 mm sphere perforates.
TEST(ShieldEquation, GivesTheDefaultShieldsCriticalDiameters) {
  EXPECT_NEAR(tc::christiansen_critical_diameter(shot(3.0, 0.1, 0.2, 3.0, 2.7, 2.7, 40.0, 0.0)),
              1.62e-3, 0.005e-3);
  EXPECT_NEAR(tc::christiansen_critical_diameter(shot(6.5, 0.1, 0.2, 3.0, 2.7, 2.7, 40.0, 0.0)),
              2.67e-3, 0.005e-3);
  const tc::ShieldEquationVerdict v =
      tc::christiansen_verdict(shot(5.0, 0.1, 0.2, 3.0, 2.7, 2.7, 40.0, 30.0, 0.30));
  EXPECT_NEAR(v.critical_diameter, 2.18e-3, 0.005e-3);
  EXPECT_TRUE(v.perforated);
  EXPECT_EQ(v.regime, tc::ShieldRegime::shatter);
  EXPECT_FALSE(
      tc::christiansen_verdict(shot(5.0, 0.1, 0.2, 3.0, 2.7, 2.7, 40.0, 30.0, 0.20)).perforated);
}

// The shipped case's shot is its parameters', its densities its bodies' materials'; a run on
// the case's own cells is not coarser, one with fewer cells through a plate or across the
// sphere is, and a larger sphere at the same cells across is not.
TEST(ShieldEquation, WhippleCaseDeclaresItsShotAndItsCells) {
  const std::string file = tc::test::source_path("data/cases/whipple.yaml");
  const tc::Case c = tc::load_case(file, {"parameters.v=5000", "parameters.theta=30"});
  ASSERT_TRUE(c.shield_equation.declared);
  const tc::WhippleShot& s = c.shield_equation.shot;
  EXPECT_EQ(s.diameter, 4.0e-3);
  EXPECT_EQ(s.speed, 5000.0);
  EXPECT_EQ(s.obliquity_deg, 30.0);
  EXPECT_EQ(s.bumper_thickness, 1.0e-3);
  EXPECT_EQ(s.standoff, 30.0e-3);
  EXPECT_EQ(s.wall_thickness, 2.0e-3);
  EXPECT_EQ(s.wall_yield, 276.0e6);
  EXPECT_EQ(s.projectile_density, c.material("projectile").density);
  EXPECT_EQ(s.bumper_density, c.material("bumper").density);
  EXPECT_EQ(c.shield_equation.verdict, "wall perforated");
  EXPECT_FALSE(c.mesh_study.coarser());
  ASSERT_EQ(c.mesh_study.cells_across.size(), 3u);
  EXPECT_FALSE(tc::load_case(file, {"parameters.d=5.0e-3"}).mesh_study.coarser());
  EXPECT_FALSE(tc::load_case(file, {"parameters.hb=0.25e-3"}).mesh_study.coarser());  // finer
  for (const char* coarser : {"parameters.hb=1.0e-3", "parameters.hw=2.0e-3", "parameters.np=6"})
    EXPECT_TRUE(tc::load_case(file, {coarser}).mesh_study.coarser()) << coarser;
  // The cells through the bumper follow its thickness: a thicker bumper at the file's hb rule
  // is not coarser.
  EXPECT_FALSE(tc::load_case(file, {"parameters.tb=2.0e-3"}).mesh_study.coarser());
}

TEST(ShieldEquation, BadDeclarationsAreRefusedNamingTheKey) {
  const std::string file = tc::test::source_path("data/cases/whipple.yaml");
  const auto refused = [&](const std::string& set, const std::string& key,
                           const std::string& what) {
    try {
      tc::load_case(file, {set});
      ADD_FAILURE() << set << " was accepted";
    } catch (const tc::CaseError& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find(key), std::string::npos) << m;
      EXPECT_NE(m.find(what), std::string::npos) << m;
    }
  };
  refused("shield_equation.verdict=wall bulge", "shield_equation.verdict",
          "no `reference:` entry of measure perforated");
  refused("shield_equation.bumper=plate", "shield_equation.bumper", "no body named 'plate'");
  refused("shield_equation.obliquity=90", "shield_equation.obliquity", "0 ≤ θ < 90");
  refused("shield_equation.wall_yield=0", "shield_equation.wall_yield", "must be positive");
  refused("mesh_study.cells_across.wall=-1", "mesh_study.cells_across.wall", "must be positive");
  // A study the file does not declare, added by overrides: nothing of the file's to compare.
  const tc::Case added =
      tc::load_case(tc::test::source_path("data/cases/cubes-edge.yaml"),
                    {"mesh_study.note=a note", "mesh_study.cells_across.cube=2"});
  ASSERT_EQ(added.mesh_study.cells_across.size(), 1u);
  EXPECT_EQ(added.mesh_study.cells_across[0].file, 2.0);
  EXPECT_FALSE(added.mesh_study.coarser());
}
