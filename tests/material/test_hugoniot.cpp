// The library's aluminium equations of state against measured shock states of aluminium
// (data/validation/aluminium-hugoniot.csv: McQueen et al. 1970 for 2024 aluminium, Mitchell &
// Nellis 1981 for pure aluminium, up to 200 GPa; read from the papers by the compiler, a few
// per cent of scatter). The engine's own pressure on its Hugoniot, p = A(μ) + Γ0 E with the
// jump condition's E = ½ p η (η = 1 − V/V0), against each measured point.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <tuple>

#include "../test_util.hpp"
#include "tetcontact/io/case.hpp"
#include "tetcontact/material/material.hpp"

using namespace tc;

namespace {

struct Shock {
  double v_over_v0, pressure;  // Pa
  std::string source;
};

std::vector<Shock> measured_shocks() {
  std::ifstream in(test::source_path("data/validation/aluminium-hugoniot.csv"));
  EXPECT_TRUE(in) << "data/validation/aluminium-hugoniot.csv";
  std::vector<Shock> out;
  for (std::string line; std::getline(in, line);) {
    line.erase(std::remove(line.begin(), line.end(), '\r'), line.end());
    if (line.empty() || line[0] == '#' || line.rfind("V_over_V0", 0) == 0) continue;
    std::stringstream ss(line);
    std::string v, p, source;
    std::getline(ss, v, ',');
    std::getline(ss, p, ',');
    std::getline(ss, source);
    out.push_back({std::stod(v), std::stod(p) * 1e9, source});
  }
  return out;
}

// The engine's pressure behind a shock to V/V0: p = A + B E with the jump condition's
// E = ½ p η, p = A / (1 − B η / 2); A and B taken at that E (Newton's iteration: Tillotson's
// depend on E, Mie–Grüneisen's do not, p = A(μ) / (1 − Γ0 η / 2) at once).
double hugoniot_pressure(const Material& m, double v_over_v0) {
  const double eta = 1.0 - v_over_v0, mu = eta / v_over_v0;
  double p = 0.0;
  for (int k = 0; k < 50; ++k) {
    const EosTerms t = eos_terms(m, mu, 0.5 * p * eta);
    p = t.a / (1.0 - 0.5 * t.b * eta);
  }
  return p;
}

const Material& entry(const std::vector<Material>& lib, const std::string& name) {
  const auto it =
      std::find_if(lib.begin(), lib.end(), [&](const Material& m) { return m.name == name; });
  if (it == lib.end()) throw std::runtime_error("no library entry " + name);
  return *it;
}

double median(std::vector<double> x) {
  std::sort(x.begin(), x.end());
  const std::size_t n = x.size();
  return n % 2 ? x[n / 2] : 0.5 * (x[n / 2 - 1] + x[n / 2]);
}

}  // namespace

// Each source against the library's entry for its alloy: 2024 aluminium (McQueen et al.) and
// the 2024-T4 entry, pure aluminium (Mitchell & Nellis) and the 1100-O entry. Measured (this
// version): above 20 GPa within 9.1 % and 7.4 % of every point, medians of |error| 3.8 % and
// 1.2 % above 50 GPa, where a Whipple shot's first microseconds live; below 20 GPa the linear
// Us–up fit is 8 % high on the 2024 points. A linear EOS (p = K μ) gives at most 0.58 of the
// measured pressure above 50 GPa.
TEST(Hugoniot, LibraryAluminiumAgainstTheMeasuredShocks) {
  const std::vector<Material> lib = load_material_library(default_material_library());
  const std::vector<Shock> shocks = measured_shocks();
  ASSERT_EQ(shocks.size(), 55u);
  for (const auto& [source, name, every, high] :
       std::vector<std::tuple<std::string, std::string, double, double>>{
           {"McQueen", "al2024-t4", 0.10, 0.05}, {"Mitchell", "al1100-o", 0.08, 0.03}}) {
    const Material& m = entry(lib, name);
    std::vector<double> above_50;
    int n = 0;
    for (const Shock& s : shocks) {
      if (s.source.find(source) == std::string::npos) continue;
      ++n;
      const double p = hugoniot_pressure(m, s.v_over_v0);
      // The engine's Hugoniot is the linear Us–up one, p = ρ0 c0² η / (1 − s η)².
      const double eta = 1.0 - s.v_over_v0;
      EXPECT_NEAR(p, m.density * m.c0 * m.c0 * eta / std::pow(1.0 - m.s * eta, 2), 1e-9 * p);
      const double error = p / s.pressure - 1.0;
      if (s.pressure >= 20e9) {
        EXPECT_LT(std::abs(error), every) << name << " at " << s.v_over_v0;
      }
      if (s.pressure >= 50e9) above_50.push_back(std::abs(error));
      // Without the Mie–Grüneisen EOS: the linear one with the same bulk modulus.
      if (s.pressure >= 50e9) {
        EXPECT_LT(m.bulk_modulus * eta / s.v_over_v0 / s.pressure, 0.6);
      }
    }
    EXPECT_GT(n, 20) << source;
    ASSERT_GT(above_50.size(), 5u) << source;
    EXPECT_LT(median(above_50), high) << name;
  }
}

// Tillotson's aluminium constants (the library's `tillotson` block, [T62]) on the same measured
// shocks: each library alloy with `eos: tillotson` against each source. Its Hugoniot is not a
// fit to these points; measured (this version): medians of |error| above 50 GPa of 8.3 %
// (McQueen, 2024-T4 entry) and 3.4 % (Mitchell, 1100-O entry), every point above 20 GPa within
// 12.3 % and 10.5 % (the library's Mie–Grüneisen: 3.8 % and 1.2 %, 9.1 % and 7.4 %).
TEST(Hugoniot, TillotsonAluminiumAgainstTheMeasuredShocks) {
  std::vector<Material> lib = load_material_library(default_material_library());
  const std::vector<Shock> shocks = measured_shocks();
  for (const auto& [source, name, every, high] :
       std::vector<std::tuple<std::string, std::string, double, double>>{
           {"McQueen", "al2024-t4", 0.15, 0.10}, {"Mitchell", "al1100-o", 0.13, 0.05}}) {
    Material m = entry(lib, name);
    ASSERT_GT(m.tillotson.big_a, 0.0) << name << " has no tillotson block";
    m.eos = EosKind::tillotson;
    m.bulk_modulus = m.tillotson.big_a;
    std::vector<double> above_50;
    double worst = 0.0;
    for (const Shock& s : shocks) {
      if (s.source.find(source) == std::string::npos) continue;
      const double p = hugoniot_pressure(m, s.v_over_v0);
      // The iteration converged: p on the EOS at the jump condition's energy.
      const double eta = 1.0 - s.v_over_v0;
      EXPECT_NEAR(p, eos_pressure(m, eta / s.v_over_v0, 0.5 * p * eta), 1e-9 * p);
      const double error = p / s.pressure - 1.0;
      if (s.pressure >= 20e9) worst = std::max(worst, std::abs(error));
      if (s.pressure >= 50e9) above_50.push_back(std::abs(error));
    }
    std::printf("%s (%s, tillotson): above 20 GPa worst %.3f, above 50 GPa median %.3f\n",
                source.c_str(), name.c_str(), worst, median(above_50));
    EXPECT_LT(worst, every) << name;
    EXPECT_LT(median(above_50), high) << name;
  }
}
