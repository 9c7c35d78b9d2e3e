// edgeLinePoints (tactile_features/edge_line.hpp) against edges pressed into
// the elastic pad model (sim::integratePad), whose line is known exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "alloc_counter.hpp"
#include "tactile_features/edge_line.hpp"
#include "tactile_sim/elastic_pad.hpp"

using namespace tactile;

namespace {

constexpr double kDeg = kPi / 180.0;

// A bar of 3 mm radius pressed 2 mm deep (about 9 N on the shipped pad: at 5 N a
// column of the 14 carries 0.36 N, and often only one of its rows reaches the
// 0.2 N threshold;
// "round" is the bar's radius) along a line through (0, y0) at `angle` to x_s,
// then the firing threshold as the WTS applies it.
TactileFrame pressEdge(double y0, double angle, double round = 0.003, double depth = 0.002) {
  TactileFrame f;
  f.force.fill(0.0);
  sim::PadGeometry g;
  g.subsamples = 8;
  sim::integratePad(g, sim::EdgeIndent{0.0, y0, angle, depth, round, 1.0}, f);
  for (double& v : f.force)
    if (v < 0.2) v = 0.0;
  return f;
}

// Distance of (x, y) from the line through (0, y0) at `angle`.
double offLine(const EdgeLinePoint& p, double y0, double angle) {
  return std::fabs(-p.x * std::sin(angle) + (p.y - y0) * std::cos(angle));
}

}  // namespace

// Sub-pitch: an edge along x_s at 11 offsets across one pitch, from the
// centre of row 2 (y0 = -1.7 mm) to the centre of row 3 (+1.7 mm). Within
// 0.68 mm of the line between the rows both rows fire in every column and
// each column gives a point; nearer a row centre only that row fires and the
// column gives none (it would be the row's centre, up to 1.7 mm off).
// Measured: the worst point 0.22 mm off the line (the pad's load profile
// across the ridge is not a triangle, so the centroid of two or three samples
// leans towards the nearer row); tolerance 0.3 mm, under a tenth of the pitch.
TEST(EdgeLine, AnEdgeAlongXBetweenTwoRowsIsFoundToATenthOfAPitch) {
  const SensorGeometry g;
  double worst = 0;
  for (int k = 0; k <= 10; ++k) {
    const double y0 = -0.0017 + 0.00034 * k;
    EdgeLinePoints pts;
    const int n = edgeLinePoints(pressEdge(y0, 0.0), g, EdgeLineParams{}, pts);
    std::printf("y0 %+.2f mm: %d columns\n", y0 * 1e3, n);
    if (std::fabs(y0) < 0.0007) EXPECT_EQ(n, g.cols) << "y0 " << y0;
    else EXPECT_EQ(n, 0) << "y0 " << y0;
    for (int i = 0; i < n; ++i) worst = std::max(worst, offLine(pts[static_cast<std::size_t>(i)], y0, 0.0));
  }
  std::printf("worst distance from the line: %.3f mm\n", worst * 1e3);
  EXPECT_LT(worst, 0.0003);
}

// A line at an angle to x_s: each column's point is where the line crosses it.
// Measured worst: 0.28, 0.32, 0.46 mm at 10, 20, 30 deg (the column's width
// spreads the line over more of its rows as the angle grows); tolerance
// 0.5 mm. Beyond about 40 deg a column has the line on more than max_rows
// rows and gives no point (the next test).
TEST(EdgeLine, ALineAtAnAngleIsFollowed) {
  const SensorGeometry g;
  for (double deg : {10.0, 20.0, 30.0}) {
    EdgeLinePoints pts;
    const int n = edgeLinePoints(pressEdge(0.0005, deg * kDeg), g, EdgeLineParams{}, pts);
    EXPECT_GE(n, 4) << deg << " deg";  // the columns where the line is inside the pad's width
    double worst = 0;
    for (int i = 0; i < n; ++i) worst = std::max(worst, offLine(pts[static_cast<std::size_t>(i)], 0.0005, deg * kDeg));
    std::printf("%g deg: %d points, worst %.3f mm\n", deg, n, worst * 1e3);
    EXPECT_LT(worst, 0.0005) << deg << " deg";
  }
}

// An edge ACROSS the columns (along y_s: the far side of a corner under the
// pad) loads whole columns: no point, rather than the middle of the edge.
// One firing row (a light touch on a row centre) gives none either.
TEST(EdgeLine, AnEdgeAcrossTheColumnsOrOneRowGivesNoPoint) {
  const SensorGeometry g;
  EdgeLinePoints pts;
  EXPECT_EQ(edgeLinePoints(pressEdge(0.0, 90 * kDeg), g, EdgeLineParams{}, pts), 0);
  TactileFrame one;
  one.force.fill(0.0);
  for (int c = 0; c < g.cols; ++c) one.at(2, c) = 0.5;
  EXPECT_EQ(edgeLinePoints(one, g, EdgeLineParams{}, pts), 0);
  TactileFrame gap = one;  // two rows apart: not contiguous
  for (int c = 0; c < g.cols; ++c) gap.at(4, c) = 0.5;
  EXPECT_EQ(edgeLinePoints(gap, g, EdgeLineParams{}, pts), 0);
}

TEST(EdgeLine, BadFramesGiveNoPointAndNoAllocation) {
  const SensorGeometry g;
  TactileFrame f = pressEdge(0.0, 0.0);
  EdgeLinePoints pts;
  f.at(2, 3) = std::nan("");  // a NaN taxel does not fire
  const test::AllocationScope count;
  const int n = edgeLinePoints(f, g, EdgeLineParams{}, pts);
  TactileFrame small = f;
  small.cols = 10;  // not the geometry's size
  const int m = edgeLinePoints(small, g, EdgeLineParams{}, pts);
  EXPECT_EQ(count.count(), 0u);
  EXPECT_GE(n, g.cols - 1);
  EXPECT_EQ(m, 0);
  for (int i = 0; i < n; ++i) EXPECT_TRUE(std::isfinite(pts[static_cast<std::size_t>(i)].y));
}
