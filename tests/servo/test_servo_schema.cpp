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
#include "tactile_servo/servo_schema.hpp"

namespace tactile {
namespace {

using schema::Block;
using schema::Kind;

/// Every Number with a numeric end: just outside that end (or NaN) is
/// refused, naming "<where>.<key> = " and the declared range; just inside is
/// accepted. A range end that names another key is checked at that key's
/// default value.
template <class S>
void expectRangesEnforced(const Block<S>& b) {
  const S d{};
  ASSERT_TRUE(schema::checkRanges(b, d, "f.yaml: " + std::string(b.name)).ok())
      << b.name << ": the defaults lie outside their ranges: "
      << schema::checkRanges(b, d, "f.yaml: " + std::string(b.name)).message();
  for (const auto& f : b.fields) {
    if (f.kind != Kind::Number) continue;
    schema::Range r;
    ASSERT_TRUE(schema::parseRange(f.range, r)) << b.name << "." << f.key << ": '" << f.range << "'";
    const std::string at = "f.yaml: " + std::string(b.name) + "." + f.key + " = ";
    auto refuse = [&](double v, const char* why) {
      S s = d;
      f.store(s, v);
      const ConfigResult c = schema::checkRanges(b, s, "f.yaml: " + std::string(b.name));
      ASSERT_FALSE(c.ok()) << b.name << "." << f.key << " = " << v << " (" << why << ") accepted";
      EXPECT_NE(c.message().find(at), std::string::npos) << c.message();
      EXPECT_NE(c.message().find(f.range), std::string::npos) << c.message();
    };
    refuse(std::nan(""), "NaN");
    double lo = 0.0, hi = 0.0;
    if (r.lo.given) lo = r.lo.key.empty() ? r.lo.value : schema::find(b, r.lo.key)->value(d);
    if (r.hi.given) hi = r.hi.key.empty() ? r.hi.value : schema::find(b, r.hi.key)->value(d);
    const double step = 1e-9 * std::max(1.0, std::max(std::fabs(lo), std::fabs(hi)));
    if (r.lo.given) refuse(r.lo.open ? lo : lo - step, "below its lower end");
    if (r.hi.given) refuse(r.hi.open ? hi : hi + step, "above its upper end");
  }
}

TEST(SchemaBlocks, EveryRangeIsReadableAndEnforced) {
  expectRangesEnforced(controllerSchema());
  expectRangesEnforced(safetySchema());
  expectRangesEnforced(watchdogSchema());
  expectRangesEnforced(forceEstimateSchema());
  expectRangesEnforced(speedLawSchema());
  expectRangesEnforced(speedLawServoSchema());
  expectRangesEnforced(slopeFeedforwardSchema());
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
  auto check = [](const auto& b) {
    for (std::size_t i = 0; i < b.fields.size(); ++i) {
      EXPECT_GT(std::string(b.fields[i].doc).size(), 8u) << b.name << "." << b.fields[i].key << ": no meaning";
      for (std::size_t j = i + 1; j < b.fields.size(); ++j)
        EXPECT_STRNE(b.fields[i].key, b.fields[j].key) << b.name << ": declared twice";
    }
  };
  check(controllerSchema());
  check(safetySchema());
  check(watchdogSchema());
  check(forceEstimateSchema());
  check(speedLawSchema());
  check(speedLawServoSchema());
  check(slopeFeedforwardSchema());
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
                        "`phases` |  | a list of names | [] |", "#### `speed_law`", "#### `slope_feedforward`"})
    EXPECT_NE(md.find(k), std::string::npos) << k << "\n" << md;
}

}  // namespace
}  // namespace tactile
