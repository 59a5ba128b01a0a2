#include <gtest/gtest.h>

#include "tetcontact/material/elastic.hpp"

using namespace tc;

TEST(Elastic, ModuliFromYoungAndPoisson) {
  Material m{"steel", 7850, 210e9, 0.3};
  EXPECT_NEAR(m.bulk_modulus(), 175e9, 1e-3 * 175e9);
  EXPECT_NEAR(m.shear_modulus(), 210e9 / 2.6, 1.0);
  // c_p² = E (1-ν) / (ρ (1+ν)(1-2ν))
  EXPECT_NEAR(m.wave_speed(), std::sqrt(210e9 * 0.7 / (7850 * 1.3 * 0.4)), 1e-9);
}

TEST(Elastic, UniaxialStrainRateGivesLameStresses) {
  Material m{"al", 2700, 70e9, 0.3};
  const double lambda = m.bulk_modulus() - 2.0 / 3.0 * m.shear_modulus();
  Mat3 L = Mat3::Zero();
  L(0, 0) = 100.0;  // 1/s
  Mat3 s = Mat3::Zero();
  double p = 0.0;
  const double tau = 1e-7;
  elastic_rate_update(m, L, tau, s, p);
  const Mat3 sigma = s - p * Mat3::Identity();
  const double e = 100.0 * tau;
  EXPECT_NEAR(sigma(0, 0), (lambda + 2 * m.shear_modulus()) * e, 1e-6);
  EXPECT_NEAR(sigma(1, 1), lambda * e, 1e-6);
  EXPECT_NEAR(sigma(2, 2), lambda * e, 1e-6);
  EXPECT_NEAR(sigma(0, 1), 0.0, 1e-9);
}

TEST(Elastic, SpinRotatesStressWithoutChangingItsInvariants) {
  // Pure spin W: the Jaumann update rotates the deviator; over one small step its norm is
  // kept to second order in τ|W|.
  Material m{"al", 2700, 70e9, 0.3};
  Mat3 s;
  s << 2, 1, 0, 1, -1, 0.5, 0, 0.5, -1;
  s *= 1e8;
  Mat3 L = Mat3::Zero();
  L(0, 1) = -1000.0;
  L(1, 0) = 1000.0;
  double p = 5e7;
  const double norm0 = s.norm();
  Mat3 s1 = s;
  elastic_rate_update(m, L, 1e-7, s1, p);
  EXPECT_NEAR(p, 5e7, 0.0);  // no volume change
  EXPECT_NEAR(s1.norm(), norm0, 1e-7 * norm0);
  EXPECT_GT((s1 - s).norm(), 1e-5 * norm0);  // it did rotate
  EXPECT_NEAR(s1.trace(), 0.0, 1e-6);
}
