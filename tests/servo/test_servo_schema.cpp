// The declared program blocks (tactile_servo/servo_schema.hpp): every
// declaration is readable, its default within its range, every range
// enforced with a message naming the key and the range, the reader's key
// checks at every nesting level, and a unit conversion read and reported in
// the file's unit.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <string>

#include "tactile_config/schema_yaml.hpp"
#include "schema_checks.hpp"
#include "tactile_servo/servo_schema.hpp"

namespace tactile {
namespace {

using schema::Kind;
using test::expectRangesEnforced;

TEST(SchemaBlocks, EveryRangeIsReadableAndEnforced) {
  expectRangesEnforced(controllerSchema());
  expectRangesEnforced(safetySchema());
  expectRangesEnforced(watchdogSchema());
  expectRangesEnforced(forceEstimateSchema());
  expectRangesEnforced(speedLawSchema());
  expectRangesEnforced(speedLawServoSchema());
  expectRangesEnforced(slopeFeedforwardSchema());
  expectRangesEnforced(phaseDefaultsSchema());
  expectRangesEnforced(phaseSchema());
  expectRangesEnforced(transitionSchema());
}

TEST(SchemaBlocks, TransitionEventNamesAreTheFileNames) {
  constexpr int kEvents = static_cast<int>(kLastTransitionEvent) + 1;
  ASSERT_EQ(schema::detail::choiceCount(transitionEventNames()), kEvents);
  for (int i = 0; i < kEvents; ++i)
    EXPECT_EQ(schema::detail::choiceName(transitionEventNames(), i), toString(static_cast<TransitionEvent>(i)));
}

TEST(SchemaBlocks, RangeSyntax) {
  schema::Range r;
  ASSERT_TRUE(schema::parseRange("(0, 1e4]", r));
  EXPECT_TRUE(r.lo.given && r.lo.open && r.lo.value == 0.0);
  EXPECT_TRUE(r.hi.given && !r.hi.open && r.hi.value == 1e4);
  ASSERT_TRUE(schema::parseRange("[0, v_max)", r));
  EXPECT_EQ(r.hi.key, "v_max");
  EXPECT_TRUE(r.hi.open);
  ASSERT_TRUE(schema::parseRange(">= 0", r));
  EXPECT_TRUE(r.lo.given && !r.lo.open && !r.hi.given);
  ASSERT_TRUE(schema::parseRange("", r));
  EXPECT_FALSE(r.lo.given || r.hi.given);
  EXPECT_FALSE(schema::parseRange("0..1", r));
  EXPECT_FALSE(schema::parseRange("(0, V-max]", r));
}

TEST(SchemaBlocks, KeysAreUniqueAndDocumented) {
  const auto check = [](const auto& b) { test::expectKeysUniqueAndDocumented(b); };
  check(controllerSchema());
  check(safetySchema());
  check(watchdogSchema());
  check(forceEstimateSchema());
  check(speedLawSchema());
  check(speedLawServoSchema());
  check(slopeFeedforwardSchema());
  check(phaseDefaultsSchema());
  check(phaseSchema());
  check(transitionSchema());
}

TEST(SchemaReader, NestedKeysDegreesAndChoices) {
  const config::Where w{"p.yaml", "watchdogs"};
  WatchdogParams p;
  ConfigResult r = config::readBlock(
      YAML::Load("{arm_stall: {min_angle_deg: 10, window_s: 2}, on_fault: retreat, retreat_m: 0.02}"), w,
      watchdogSchema(), p);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_DOUBLE_EQ(p.stall_min_angle, 10.0 * 3.14159265358979323846 / 180.0);
  EXPECT_DOUBLE_EQ(p.stall_window_s, 2.0);
  EXPECT_TRUE(p.fault_retreat);
  EXPECT_DOUBLE_EQ(p.fault_retreat_m, 0.02);
  EXPECT_DOUBLE_EQ(p.unseen_max_n, WatchdogParams{}.unseen_max_n) << "an absent key keeps its value";

  r = config::readBlock(YAML::Load("{arm_stall: {window: 2}}"), w, watchdogSchema(), p);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("p.yaml: watchdogs.arm_stall.window: unknown key (allowed: window_s, min_distance, "
                             "min_angle_deg, min_fraction)"),
            std::string::npos)
      << r.message();
  r = config::readBlock(YAML::Load("{arm_stal: {window_s: 2}}"), w, watchdogSchema(), p);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("watchdogs.arm_stal: unknown key (allowed: arm_stall, force_mismatch"), std::string::npos)
      << r.message();
  r = config::readBlock(YAML::Load("{on_fault: flee}"), w, watchdogSchema(), p);
  EXPECT_NE(r.message().find("watchdogs.on_fault: 'flee': must be one of hold, retreat"), std::string::npos)
      << r.message();
  r = config::readBlock(YAML::Load("{retreat_m: far}"), w, watchdogSchema(), p);
  EXPECT_NE(r.message().find("watchdogs.retreat_m: cannot parse 'far'"), std::string::npos) << r.message();

  // Out of range: reported in the file's unit (degrees), with its range.
  p.stall_min_angle = 200.0 * 3.14159265358979323846 / 180.0;
  r = schema::checkRanges(watchdogSchema(), p, "p.yaml: watchdogs");
  EXPECT_NE(r.message().find("p.yaml: watchdogs.arm_stall.min_angle_deg = 200: must be in (0, 180] deg"),
            std::string::npos)
      << r.message();
}

TEST(SchemaReader, VariantsRequireTheirKeysAndRefuseOthers) {
  const config::Where w{"p.yaml", "phases.hold.transitions[0]"};
  auto read = [&](const char* yaml, TransitionParams& t) {
    return config::readBlock(YAML::Load(yaml), w, transitionSchema(), t);
  };
  TransitionParams t;
  ConfigResult r = read("{on: joint_margin, to: a, angle_deg: 12}", t);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(t.on, TransitionEvent::JointMargin);
  EXPECT_DOUBLE_EQ(t.angle_rad, 12.0 * 3.14159265358979323846 / 180.0);
  t = TransitionParams{};
  r = read("{on: timeout, to: a}", t);
  EXPECT_NE(r.message().find("p.yaml: phases.hold.transitions[0].timeout_s: required for 'timeout'"), std::string::npos)
      << r.message();
  t = TransitionParams{};
  r = read("{on: contact, to: a, force_n: 3}", t);
  EXPECT_NE(r.message().find("transitions[0].force_n: only for 'force_above'"), std::string::npos) << r.message();
  t = TransitionParams{};
  r = read("{on: edge, to: a, angle_deg: 3}", t);  // one key, two variants' declarations
  EXPECT_NE(r.message().find("angle_deg: only for 'wrist_wound', 'wrist_unwound' and 'joint_margin'"),
            std::string::npos)
      << r.message();
  t = TransitionParams{};
  r = read("{on: edge}", t);
  EXPECT_NE(r.message().find("transitions[0].to: required"), std::string::npos) << r.message();
  // The range of a key declared per variant is that variant's.
  t = TransitionParams{};
  ASSERT_TRUE(read("{on: wrist_wound, to: a, angle_deg: 200}", t).ok());
  EXPECT_TRUE(schema::checkRanges(transitionSchema(), t, w.str()).ok());
  t.on = TransitionEvent::JointMargin;
  r = schema::checkRanges(transitionSchema(), t, w.str());
  EXPECT_NE(r.message().find("transitions[0].angle_deg = 200: must be in (0, 30] deg"), std::string::npos)
      << r.message();
}

TEST(SchemaReader, VectorsAsListsOrMappings) {
  const config::Where w{"p.yaml", "phases.hold"};
  PhaseParams ph;
  ph.kp.setConstant(7.0);
  ConfigResult r = config::readBlock(YAML::Load("{name: hold, kp_per_s: {y: 2.5, wz: 1}, ki_per_s2: [1, 2, 3, 4, 5, 6]}"),
                                     w, phaseSchema(), ph);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(ph.kp(1), 2.5);
  EXPECT_EQ(ph.kp(5), 1.0);
  EXPECT_EQ(ph.kp(0), 7.0) << "an entry not given keeps its value";
  EXPECT_EQ(ph.ki(3), 4.0);
  r = config::readBlock(YAML::Load("{kp_per_s: {q: 1}}"), w, phaseSchema(), ph);
  EXPECT_NE(r.message().find("phases.hold.kp_per_s.q: unknown name (allowed: x, y, z, wx, wy, wz)"), std::string::npos)
      << r.message();
  r = config::readBlock(YAML::Load("{feedforward: [0, 0, 0]}"), w, phaseSchema(), ph);
  EXPECT_NE(r.message().find("phases.hold.feedforward: must have 6 entries, has 3"), std::string::npos) << r.message();
  ph.u_max(kWY) = 0.0;
  r = schema::checkRanges(phaseSchema(), ph, w.str());
  EXPECT_NE(r.message().find("p.yaml: phases.hold.u_max_per_s.wy = 0: must be > 0 m/s, rad/s"), std::string::npos)
      << r.message();
}

TEST(SchemaReader, OneFileBlockOverTwoStructs) {
  const config::Where w{"p.yaml", "speed_law"};
  SpeedLawConfig c;
  const YAML::Node n = YAML::Load("{phases: [explore], axis: y, v_max: 0.08, force_budget_n: 0.4}");
  ConfigResult r = config::readBlock(n, w, speedLawServoSchema(), c, config::keysOf(speedLawSchema()));
  ASSERT_TRUE(r.ok()) << r.message();
  r = config::readBlock(n, w, speedLawSchema(), c.law, config::keysOf(speedLawServoSchema()));
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(c.phases, std::vector<std::string>{"explore"});
  EXPECT_EQ(c.axis, 1);
  EXPECT_DOUBLE_EQ(c.law.v_max, 0.08);
  EXPECT_DOUBLE_EQ(c.law.force_budget_n, 0.4);
  c.law.v_min = 0.1;  // above v_max: a range that names another key
  r = schema::checkRanges(speedLawSchema(), c.law, "p.yaml: speed_law");
  EXPECT_NE(r.message().find("p.yaml: speed_law.v_min = 0.1: must be in [0, v_max] m/s"), std::string::npos)
      << r.message();
}

TEST(SchemaDocs, TablesListEveryKeyWithItsDefault) {
  const std::string md = programSchemaMarkdown();
  for (const char* k : {"`max_rot_speed_deg` | deg/s | (0, 573] | 50 |", "`arm_stall.min_angle_deg` | deg | (0, 180] | 5 |",
                        "`contact_loss.mode` |  | hold, backoff, search | hold |", "`crawl_mps` | m/s | [0, v_max] | 0 |",
                        "`phases` |  | a list of names | [] |", "#### `speed_law`", "#### `slope_feedforward`",
                        "`angle_deg` | deg | (0, 30]; only for 'joint_margin'; required | 0 |",
                        "`kp_per_s` | 1/s | each >= 0; a list of 6 or a mapping over x, y, z, wx, wy, wz | [0, 0, 0, 0, 0, 0] |",
                        "#### `phases[]`", "#### `transitions[]`", "#### `phase_defaults`"})
    EXPECT_NE(md.find(k), std::string::npos) << k << "\n" << md;
}

}  // namespace
}  // namespace tactile
