// The declared `features:` and `calibration:` blocks (tactile_features/features_schema.hpp):
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
  test::expectRangesEnforced(calibrationSchema());
  test::expectKeysUniqueAndDocumented(calibrationSchema());
}

// calibration: the reader and Calibration::configure check the same declared
// ranges; the lists stay the reader's own; the defaults are CalibrationParams'.
TEST(FeaturesSchema, CalibrationReaderAndMessages) {
  CalibrationParams p;
  const config::Where w{"s.yaml", "calibration"};
  ConfigResult r = loadCalibrationParams(YAML::Load("{full_scale: 3000, max_tare: 100, coeffs: [0, 0.001]}"), w, 6, 14, p);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(p.full_scale, 3000);
  EXPECT_EQ(p.max_tare, 100);
  EXPECT_DOUBLE_EQ(p.coeffs[1], 0.001);
  r = loadCalibrationParams(YAML::Load("{full_scale: 3000, max_tare: 3001}"), w, 6, 14, p);
  EXPECT_NE(r.message().find("s.yaml: calibration.max_tare = 3001: must be in [0, full_scale]"), std::string::npos)
      << r.message();
  r = loadCalibrationParams(YAML::Load("{ful_scale: 3000}"), w, 6, 14, p);
  EXPECT_NE(r.message().find("s.yaml: calibration.ful_scale: unknown key (allowed: full_scale"), std::string::npos)
      << r.message();
  CalibrationParams direct;
  direct.noise_counts = 2000.0;
  Calibration c;
  r = c.configure(direct);
  EXPECT_NE(r.message().find("calibration.noise_counts = 2000: must be in [0, 1000] counts"), std::string::npos)
      << r.message();
  const CalibrationFile d;
  EXPECT_EQ(d.full_scale, CalibrationParams{}.full_scale);
  EXPECT_EQ(d.max_tare, CalibrationParams{}.max_tare);
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
