// edgeLinePoints (tactile_features/edge_line.hpp) against edges pressed into
// the elastic pad model (sim::integratePad), whose line is known exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "alloc_counter.hpp"
#include "tactile_features/edge_line.hpp"
#include "tactile_sim_contact/elastic_pad.hpp"

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

// ---- edgeLineCurvature -------------------------------------------------------

namespace {

// The 14 column centres on a circle of radius R tangent to x_s at the pad's
// centre (its centre at (0, R)), through (x, R - sign(R) sqrt(R^2 - x^2)).
EdgeLinePoints arc(double R, int& n) {
  const SensorGeometry g;
  EdgeLinePoints pts;
  n = g.cols;
  for (int c = 0; c < n; ++c) {
    const double x = g.x(c);
    pts[static_cast<std::size_t>(c)] = {x, R - std::copysign(std::sqrt(R * R - x * x), R)};
  }
  return pts;
}

}  // namespace

// The parabola's curvature against the circle's: over the pad's 44.2 mm of
// column centres the circle departs from its osculating parabola by x^4 /
// (8 R^3) (at most 0.04 mm at R = 80 mm), which the fit absorbs into c: the
// curvature is found to 2 % of 1/R (measured 0.01-1.9 % for R 80..1000 mm,
// the largest at the tightest).
TEST(EdgeLine, TheCurvatureOfAnArcIsItsInverseRadius) {
  for (double R : {0.08, 0.182, 0.5, 1.0, -0.12}) {
    int n = 0;
    const EdgeLinePoints pts = arc(R, n);
    double k = 99;
    ASSERT_TRUE(edgeLineCurvature(pts, n, 5, 0.0136, k)) << R;
    std::printf("R %+.3f m: kappa %+.4f 1/m (1/R %+.4f)\n", R, k, 1.0 / R);
    EXPECT_NEAR(k * R, 1.0, 0.02) << R;
  }
}

// A straight line at any angle has none; a line the pad's columns do not
// resolve (too few points, too short a span, a non-finite point) gives false and 0.
TEST(EdgeLine, AStraightOrUnresolvedLineHasNoCurvature) {
  const SensorGeometry g;
  EdgeLinePoints pts;
  for (int c = 0; c < g.cols; ++c) pts[static_cast<std::size_t>(c)] = {g.x(c), 0.0007 + 0.36 * g.x(c)};  // 20 deg
  double k = 99;
  EXPECT_TRUE(edgeLineCurvature(pts, g.cols, 5, 0.0136, k));
  EXPECT_NEAR(k, 0.0, 1e-9);
  EXPECT_FALSE(edgeLineCurvature(pts, 4, 5, 0.0, k));  // fewer than min_points
  EXPECT_EQ(k, 0.0);
  EXPECT_FALSE(edgeLineCurvature(pts, 4, 3, 0.0136, k));  // 4 columns span 10.2 mm
  EXPECT_EQ(k, 0.0);
  pts[3].y = std::nan("");
  EXPECT_FALSE(edgeLineCurvature(pts, g.cols, 5, 0.0136, k));
  EXPECT_EQ(k, 0.0);
}

// Pressed into the elastic pad: an edge along x_s between two rows, straight,
// has a curvature within the points' noise (0.22 mm worst over 44 mm:
// |kappa| < 1 1/m, R > 1 m); the extractor reports it as ContactFeatures::curvature.
TEST(EdgeLine, APressedStraightEdgeIsStraight) {
  EdgeLinePoints pts;
  const int n = edgeLinePoints(pressEdge(0.0, 0.0), SensorGeometry{}, EdgeLineParams{}, pts);
  ASSERT_EQ(n, 14);
  double k = 99;
  ASSERT_TRUE(edgeLineCurvature(pts, n, 5, 0.0136, k));
  EXPECT_LT(std::fabs(k), 1.0);
}

TEST(EdgeLine, TheCurvatureDoesNotAllocate) {
  int n = 0;
  const EdgeLinePoints pts = arc(0.2, n);
  double k = 0;
  test::AllocationScope scope;
  for (int i = 0; i < 100; ++i) edgeLineCurvature(pts, n, 5, 0.0136, k);
  EXPECT_EQ(scope.count(), 0u);
}
