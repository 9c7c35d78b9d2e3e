// Elastic-foundation model of the sensing layer (used by the simulator and by
// the analytic ground-truth tests).
//
// The elastic layer is a bed of independent springs (Winkler foundation):
// pressure at a point of the surface is p = k * max(0, delta), with delta the
// local penetration of the object into the layer (m) and k the foundation
// modulus (Pa/m). The force on a taxel is the integral of p over the taxel's
// pitch x pitch cell, evaluated with K x K midpoint sub-samples. Positions are
// in {s} (conventions.hpp). With C_z the translational compliance of Eq. 2 and
// A the contact area, k = 1 / (C_z * A) for a flat indenter.
//
// The same integration also returns the ground truth of the continuous
// pressure field (total force, pressure centre, moments about x_s and y_s),
// which is what an ATI Nano17 under the sensor would measure (App. A).
#pragma once

#include <cmath>

#include "tactile_types/types.hpp"

namespace tactile {
namespace sim {

struct PadGeometry {
  int rows = kDefaultRows;
  int cols = kDefaultCols;
  double pitch = kDefaultPitch;  ///< m
  double modulus = 2.0e7;        ///< foundation modulus k (Pa/m): ~1800 N/m over an edge contact of ~1e-4 m^2
  int subsamples = 4;            ///< K: K x K samples per taxel
};

/// Ground truth of the continuous pressure field over the sensing area.
struct PadTruth {
  double force = 0.0;            ///< N
  double cop_x = 0.0, cop_y = 0.0;  ///< pressure centre (m), {s}
  double moment_x = 0.0;         ///< sum y * p dA (N m): moment about x_s
  double moment_y = 0.0;         ///< -sum x * p dA (N m): moment about y_s
};

/// Integrate `penetration(x, y) -> delta (m)` over every taxel. Allocation-free.
template <typename Penetration>
void integratePad(const PadGeometry& g, Penetration&& penetration, TactileFrame& out, PadTruth* truth = nullptr) {
  out.rows = static_cast<uint16_t>(g.rows);
  out.cols = static_cast<uint16_t>(g.cols);
  out.saturated_count = 0;
  const int k = g.subsamples < 1 ? 1 : g.subsamples;
  const double h = g.pitch / k;
  const double dA = h * h;
  double F = 0, Mx = 0, My = 0;
  for (int r = 0; r < g.rows; ++r) {
    const double yc = (r - (g.rows - 1) / 2.0) * g.pitch;
    for (int c = 0; c < g.cols; ++c) {
      const double xc = (c - (g.cols - 1) / 2.0) * g.pitch;
      double f = 0.0;
      for (int i = 0; i < k; ++i) {
        const double y = yc - 0.5 * g.pitch + (i + 0.5) * h;
        for (int j = 0; j < k; ++j) {
          const double x = xc - 0.5 * g.pitch + (j + 0.5) * h;
          const double d = penetration(x, y);
          if (d > 0.0) {
            const double df = g.modulus * d * dA;
            f += df;
            Mx += y * df;
            My += x * df;
          }
        }
      }
      out.force[static_cast<std::size_t>(r * g.cols + c)] = f;
      F += f;
    }
  }
  if (truth) {
    truth->force = F;
    truth->cop_x = F > 0 ? My / F : 0.0;
    truth->cop_y = F > 0 ? Mx / F : 0.0;
    truth->moment_x = Mx;
    truth->moment_y = -My;
  }
}

/// Sphere of radius R whose lowest point is at (x0, y0) and indents the layer
/// by depth d (m): delta = d - (R - sqrt(R^2 - rho^2)).
struct SphereIndent {
  double x0, y0, radius, depth;
  double operator()(double x, double y) const {
    const double r2 = (x - x0) * (x - x0) + (y - y0) * (y - y0);
    if (r2 >= radius * radius) return -1.0;
    return depth - (radius - std::sqrt(radius * radius - r2));
  }
};

/// Straight edge (a cylinder of radius `round` lying in the surface plane) at
/// angle `angle` from x_s, passing through (x0, y0), of finite length `length`
/// centred there, pressing by `depth` at its centre with a linear depth
/// gradient `slope` (m/m) along the edge (a non-uniform line load, Fig. 3c).
struct EdgeIndent {
  double x0, y0, angle, depth, round = 0.002, length = 1.0, slope = 0.0;
  double operator()(double x, double y) const {
    const double c = std::cos(angle), s = std::sin(angle);
    const double u = (x - x0) * c + (y - y0) * s;   // along the edge
    const double v = -(x - x0) * s + (y - y0) * c;  // across the edge
    if (std::fabs(u) > 0.5 * length) return -1.0;
    return depth + slope * u - v * v / (2.0 * round);
  }
};

}  // namespace sim
}  // namespace tactile
