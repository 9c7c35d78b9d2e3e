// The declared scene blocks (tactile_sim/sim_schema.hpp): every range
// readable and enforced with its message, the defaults inside them, each key
// declared once with a meaning.
#include <gtest/gtest.h>

#include "schema_checks.hpp"
#include "tactile_sim/sim_schema.hpp"

namespace tactile {
namespace {

TEST(SimSchema, EveryRangeIsReadableAndEnforced) {
  test::expectRangesEnforced(sim::sensorSchema());
  test::expectRangesEnforced(sim::worldEffectsSchema());
  test::expectKeysUniqueAndDocumented(sim::sensorSchema());
  test::expectKeysUniqueAndDocumented(sim::worldEffectsSchema());
}

}  // namespace
}  // namespace tactile
