// The declared scene blocks (tactile_sim_lwr/sim_schema.hpp): every range
// readable and enforced with its message, the defaults inside them, each key
// declared once with a meaning.
#include <gtest/gtest.h>

#include "schema_checks.hpp"
#include "tactile_sim_lwr/sim_schema.hpp"

namespace tactile {
namespace {

TEST(SimSchema, EveryRangeIsReadableAndEnforced) {
  test::expectRangesEnforced(sim::sensorSchema());
  test::expectRangesEnforced(sim::worldEffectsSchema());
  test::expectRangesEnforced(sim::armSchema());
  test::expectRangesEnforced(sim::sensorEffectsSchema());
  test::expectKeysUniqueAndDocumented(sim::sensorSchema());
  test::expectKeysUniqueAndDocumented(sim::worldEffectsSchema());
  test::expectKeysUniqueAndDocumented(sim::armSchema());
  test::expectKeysUniqueAndDocumented(sim::sensorEffectsSchema());
}

// LwrArm::configure checks the scene's arm keys against the declaration (the
// same message as the scene reader's), the others on its own.
TEST(SimSchema, TheArmChecksItsDeclaredRanges) {
  sim::LwrArm arm;
  sim::ArmParams p;
  ASSERT_TRUE(arm.configure(p).ok());
  p.damping_ratio = 10.5;
  const ConfigResult r = arm.configure(p);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.message(), "arm.damping_ratio = 10.5: must be in [0, 10]");
  p = sim::ArmParams();
  p.dyn_refresh_qd = -0.1;
  EXPECT_FALSE(arm.configure(p).ok());
}

}  // namespace
}  // namespace tactile
