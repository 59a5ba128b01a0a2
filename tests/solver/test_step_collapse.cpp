// The warning a fall of the time step raises names what sets the step: a tet, or an SPH
// particle with the body and tet it was made of.
#include <gtest/gtest.h>

#include <string>

#include "tetcontact/solver/simulation.hpp"

namespace tc {
namespace {

StepCollapse fall() {
  StepCollapse c;
  c.step = 120;
  c.t = 2e-7;
  c.dt = 1e-10;
  c.first_dt = 4e-9;
  c.tet = 540;
  c.body = "projectile";
  c.body_tet = 40;
  c.volume_ratio = 1.9;
  c.damage = 1;
  c.steps_to_end = 1000;
  return c;
}

TEST(StepCollapse, TheWarningNamesTheTetOrTheParticleThatSetsTheStep) {
  const std::string by_tet = fall().message();
  EXPECT_NE(by_tet.find("40x below the first"), std::string::npos) << by_tet;
  EXPECT_NE(by_tet.find("set by body 'projectile', tet 40 at"), std::string::npos) << by_tet;
  EXPECT_EQ(by_tet.find("SPH particle"), std::string::npos) << by_tet;
  StepCollapse c = fall();
  c.particle = 12;
  const std::string by_particle = c.message();
  EXPECT_NE(by_particle.find("set by SPH particle 12 (made of body 'projectile', tet 40) at"),
            std::string::npos)
      << by_particle;
  EXPECT_NE(by_particle.find("damaged"), std::string::npos) << by_particle;
}

}  // namespace
}  // namespace tc
