// The declared `features:` block (tactile_features/features_schema.hpp):
// every range readable and enforced, the ranges that restate a constant of
// the code equal to it, the reader's unknown-key error, and the table.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <string>

#include "schema_checks.hpp"
#include "tactile_features/features_schema.hpp"
#include "tactile_features/params_io.hpp"

namespace tactile {
namespace {

TEST(FeaturesSchema, EveryRangeIsReadableAndEnforced) {
  test::expectRangesEnforced(featuresSchema());
  test::expectKeysUniqueAndDocumented(featuresSchema());
}

TEST(FeaturesSchema, RangesAreTheCodesLimits) {
  const auto& b = featuresSchema();
  schema::Range r;
  ASSERT_TRUE(schema::parseRange(schema::find(b, "rows")->range, r));
  EXPECT_EQ(r.hi.value, kMaxRows);
  ASSERT_TRUE(schema::parseRange(schema::find(b, "cols")->range, r));
  EXPECT_EQ(r.hi.value, kMaxCols);
  ASSERT_TRUE(schema::parseRange(schema::find(b, "region_min_rate")->range, r));
  EXPECT_EQ(r.lo.value, kMinFiringRate);
  EXPECT_EQ(std::string(schema::find(b, "threshold")->shown), schema::detail::number(FeatureParams{}.threshold));
}

TEST(FeaturesSchema, ReaderAndMessages) {
  FeatureParams p;
  ConfigResult r = loadFeatureParams(YAML::Load("{rows: 4, alpha_hysteresis_deg: 20, threshold: otsu}"),
                                     config::Where{"s.yaml", "features"}, p);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(p.rows, 4);
  EXPECT_DOUBLE_EQ(p.alpha_hysteresis, 20.0 * kPi / 180.0);
  EXPECT_EQ(p.threshold_mode, ThresholdMode::Otsu);
  r = loadFeatureParams(YAML::Load("{edge_ration: 5}"), config::Where{"s.yaml", "features"}, p);
  EXPECT_NE(r.message().find("s.yaml: features.edge_ration: unknown key (allowed: rows, cols, pitch"), std::string::npos)
      << r.message();
  r = loadFeatureParams(YAML::Load("{alpha_hysteresis_deg: 50}"), config::Where{"s.yaml", "features"}, p);
  EXPECT_NE(r.message().find("s.yaml: features.alpha_hysteresis_deg = 50: must be in [0, 45] deg"), std::string::npos)
      << r.message();
  EXPECT_NE(sensorSchemaMarkdown().find("| `edge_ratio_exit` |  | [1, edge_ratio] | 4 |"), std::string::npos)
      << sensorSchemaMarkdown();
}

}  // namespace
}  // namespace tactile
