#include "tactile_features/edge_line.hpp"

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

}  // namespace tactile
