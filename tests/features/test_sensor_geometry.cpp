// SensorGeometry: the {s} taxel layout of conventions.hpp, and the feature
// extractor's use of it.
#include <gtest/gtest.h>

#include <limits>

#include "tactile_features/extractor.hpp"
#include "tactile_types/sensor_geometry.hpp"

using namespace tactile;

TEST(SensorGeometry, Wts0614TaxelCentresInS) {
  const SensorGeometry g;  // WTS0614: 6 x 14, 3.4 mm
  EXPECT_EQ(g.rows, 6);
  EXPECT_EQ(g.cols, 14);
  EXPECT_EQ(g.taxels(), 84);
  // x along the 14 columns, centred: outermost centres at +-6.5 pitches.
  EXPECT_DOUBLE_EQ(g.x(0), -6.5 * 0.0034);
  EXPECT_DOUBLE_EQ(g.x(13), 6.5 * 0.0034);
  EXPECT_DOUBLE_EQ(g.x(6), -0.5 * 0.0034);
  EXPECT_DOUBLE_EQ(g.x(7), 0.5 * 0.0034);
  // y along the 6 rows, row 0 at negative y.
  EXPECT_DOUBLE_EQ(g.y(0), -2.5 * 0.0034);
  EXPECT_DOUBLE_EQ(g.y(5), 2.5 * 0.0034);
  // A fractional pixel coordinate on the same line: the array centre is the origin.
  EXPECT_DOUBLE_EQ(g.x(6.5), 0.0);
  EXPECT_DOUBLE_EQ(g.y(2.5), 0.0);
  EXPECT_DOUBLE_EQ(g.width(), 14 * 0.0034);
  EXPECT_DOUBLE_EQ(g.height(), 6 * 0.0034);
  EXPECT_EQ(g.index(2, 7), 2 * 14 + 7);
}

TEST(SensorGeometry, SubSamplesTileTheTaxelCell) {
  const SensorGeometry g{3, 5, 0.01};
  const int k = 4;
  // Midpoints of k equal strips of [x(c) - pitch/2, x(c) + pitch/2].
  EXPECT_DOUBLE_EQ(g.sampleX(0, 0, k), g.x(0) - 0.005 + 0.00125);
  EXPECT_DOUBLE_EQ(g.sampleX(4, k - 1, k), g.x(4) + 0.005 - 0.00125);
  EXPECT_DOUBLE_EQ(g.sampleY(1, 0, k), -0.005 + 0.00125);
  // Mean of the samples is the taxel centre; neighbours' samples are one pitch / k apart.
  double mean = 0;
  for (int j = 0; j < k; ++j) mean += g.sampleX(2, j, k) / k;
  EXPECT_NEAR(mean, g.x(2), 1e-15);
  EXPECT_NEAR(g.sampleX(3, 0, k) - g.sampleX(2, k - 1, k), 0.01 / k, 1e-15);
  EXPECT_DOUBLE_EQ(g.sampleX(2, 0, 1), g.x(2));
}

TEST(SensorGeometry, Validity) {
  EXPECT_TRUE(SensorGeometry{}.valid());
  EXPECT_TRUE((SensorGeometry{kMaxRows, kMaxCols, 0.001}.valid()));
  EXPECT_FALSE((SensorGeometry{0, 14, 0.0034}.valid()));
  EXPECT_FALSE((SensorGeometry{6, kMaxCols + 1, 0.0034}.valid()));
  EXPECT_FALSE((SensorGeometry{6, 14, 0.0}.valid()));
  EXPECT_FALSE((SensorGeometry{6, 14, -0.0034}.valid()));
  EXPECT_FALSE((SensorGeometry{6, 14, std::numeric_limits<double>::infinity()}.valid()));
  EXPECT_FALSE((SensorGeometry{6, 14, std::numeric_limits<double>::quiet_NaN()}.valid()));
  static_assert(SensorGeometry{}.x(13) > 0.0, "usable in constant expressions");
}

TEST(SensorGeometry, FeatureExtractorUsesIt) {
  FeatureParams p;
  p.rows = 4;
  p.cols = 9;
  p.pitch = 0.005;
  const SensorGeometry g = p.geometry();
  EXPECT_EQ(g.rows, 4);
  EXPECT_EQ(g.cols, 9);
  EXPECT_EQ(g.pitch, 0.005);
  FeatureExtractor ex;
  ASSERT_TRUE(ex.configure(p).ok());
  for (int c = 0; c < p.cols; ++c) EXPECT_EQ(ex.taxelX(c), g.x(c)) << c;
  for (int r = 0; r < p.rows; ++r) EXPECT_EQ(ex.taxelY(r), g.y(r)) << r;
  // One loaded taxel: its centre is the centre of pressure.
  TactileFrame f;
  f.rows = 4;
  f.cols = 9;
  f.at(3, 1) = 2.0;
  ContactFeatures out;
  ASSERT_EQ(ex.step(f, out), FeatureStatus::Ok);
  EXPECT_DOUBLE_EQ(out.cop_x, g.x(1));
  EXPECT_DOUBLE_EQ(out.cop_y, g.y(3));
}
