#include "tactile_features/edge_line.hpp"

#include <Eigen/Dense>
#include <cmath>

namespace tactile {

int edgeLinePoints(const TactileFrame& frame, const SensorGeometry& g, const EdgeLineParams& p,
                   EdgeLinePoints& out) noexcept {
  if (frame.rows != g.rows || frame.cols != g.cols || g.cols > kMaxCols) return 0;
  int n = 0;
  for (int c = 0; c < g.cols; ++c) {
    int first = -1, last = -1, firing = 0;
    double load = 0, moment = 0;
    for (int r = 0; r < g.rows; ++r) {
      const double f = frame.at(r, c);
      if (!(f >= p.fire_n)) continue;  // also NaN
      if (first < 0) first = r;
      last = r;
      ++firing;
      load += f;
      moment += f * g.y(r);
    }
    // Contiguous, 2..max_rows rows; a load (fire_n may be 0: zero taxels then count).
    if (firing < 2 || firing > p.max_rows || last - first + 1 != firing || !(load > 0.0)) continue;
    out[static_cast<std::size_t>(n++)] = EdgeLinePoint{g.x(c), moment / load};
  }
  return n;
}

bool edgeLineCurvature(const EdgeLinePoints& pts, int n, int min_points, double min_span_m, double& kappa) noexcept {
  kappa = 0.0;
  if (n < 3 || n < min_points || n > static_cast<int>(pts.size())) return false;
  double xmin = pts[0].x, xmax = pts[0].x;
  // Normal equations of the parabola, on x centred at the pad (fixed size: no allocation).
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  Eigen::Vector3d r = Eigen::Vector3d::Zero();
  for (int i = 0; i < n; ++i) {
    const double x = pts[static_cast<std::size_t>(i)].x, y = pts[static_cast<std::size_t>(i)].y;
    if (!std::isfinite(x) || !std::isfinite(y)) return false;
    xmin = std::fmin(xmin, x);
    xmax = std::fmax(xmax, x);
    const Eigen::Vector3d phi(1.0, x, x * x);
    A.noalias() += phi * phi.transpose();
    r.noalias() += phi * y;
  }
  if (!(xmax - xmin >= min_span_m)) return false;
  const Eigen::Vector3d abc = A.ldlt().solve(r);
  if (!abc.allFinite()) return false;
  const double b = abc(1), c = abc(2);
  const double k = 2.0 * c / std::pow(1.0 + b * b, 1.5);
  if (!std::isfinite(k)) return false;
  kappa = k;
  return true;
}

}  // namespace tactile
