// The contact line of an edge, sampled column by column (beyond the paper: a
// reconstruction aid for exploration; the controller does not use it).
//
// One CoP per frame is the centroid of the whole contact: on a curved or
// cornered edge it lies inside the curve (lambda1 / (2 R) on an arc) or cuts
// the corner. The image has more: across each taxel column (x_s fixed) an
// edge lying along x_s loads two or three neighbouring rows, and the
// pressure-weighted mean of their y_s is where the edge crosses that column,
// to a fraction of the pitch (the load profile across a ridge is symmetric,
// and so is what the firing threshold cuts off it).
//
// A column gives a point when 2 <= n <= max_rows of its taxels fire (>=
// fire_n, the features' contact_threshold), contiguous: one firing row has no
// sub-pitch information (its centre, up to half a pitch off), and a wider run
// is a part of the edge running ACROSS the column (the far side of a
// corner), whose centroid is the middle of that part.
// Points are in {s} (m), on the pad surface (z_s = 0).
//
// Real-time: no allocation, no exception; out has room for every column.
#pragma once

#include <array>

#include "tactile_types/sensor_geometry.hpp"
#include "tactile_types/types.hpp"

namespace tactile {

struct EdgeLineParams {
  double fire_n = 0.2;  ///< N, least force of a firing taxel (pass FeatureParams::contact_threshold)
  int max_rows = 3;     ///< most firing rows in a column that still give a point
};

struct EdgeLinePoint {
  double x = 0, y = 0;  ///< {s}, m
};

using EdgeLinePoints = std::array<EdgeLinePoint, kMaxCols>;

/// Fills out[0..n) and returns n (0 with no usable column; a frame whose
/// rows/cols differ from the geometry's gives 0).
int edgeLinePoints(const TactileFrame& frame, const SensorGeometry& g, const EdgeLineParams& p,
                   EdgeLinePoints& out) noexcept;

/// The in-plane curvature (1/m) of the contact line at the pad's centre: the
/// least-squares parabola y = a + b x + c x^2 through pts[0..n), kappa =
/// 2 c / (1 + b^2)^(3/2), positive when the line bends towards +y_s. False
/// (kappa 0) with fewer than min_points points or a span along x_s below
/// min_span_m (m): too short a line has no curvature above the points'
/// sub-pitch noise. The speed law's look-ahead (tactile_servo/speed_law.hpp):
/// a bend entering the pad shows here before the edge angle turns.
bool edgeLineCurvature(const EdgeLinePoints& pts, int n, int min_points, double min_span_m, double& kappa) noexcept;

}  // namespace tactile
