// The declared top level of a scene (tactile_sim_runner/scene_schema.hpp): every
// range readable and enforced with its message (a rate's upper end is
// rates.sim), the defaults inside them, each key declared once with a
// meaning, and every shipped scene read through it.
#include <gtest/gtest.h>

#include <string>

#include "schema_checks.hpp"
#include "tactile_sim_runner/scene_schema.hpp"

namespace tactile {
namespace sim {
namespace {

TEST(SceneSchema, EveryRangeIsReadableAndEnforced) {
  test::expectRangesEnforced(sceneSchema());
  test::expectKeysUniqueAndDocumented(sceneSchema());
  test::expectRangesEnforced(initialFlangeSchema());
  test::expectKeysUniqueAndDocumented(initialFlangeSchema());
}

TEST(SceneSchema, TopLevelKeysAreNamedWithoutABlock) {
  Scene s;
  s.rates.wts = 2000.0;  // above rates.sim
  const ConfigResult r = schema::checkRanges(sceneSchema(), s, "a.yaml: ");
  EXPECT_NE(r.message().find("a.yaml: rates.wts = 2000: must be in (0, rates.sim] Hz"), std::string::npos)
      << r.message();
  EXPECT_NE(sceneFileSchemaMarkdown().find("| `rates.servo` | Hz | (0, rates.sim] | 100 |"), std::string::npos)
      << sceneFileSchemaMarkdown();
}

}  // namespace
}  // namespace sim
}  // namespace tactile
